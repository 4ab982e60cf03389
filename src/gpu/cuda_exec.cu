// SPDX-License-Identifier: GPL-3.0-or-later
// The CUDA back end of the device step: the bodies of kernels.hpp as kernels with one thread per
// grain, arrays in device memory (plain cudaMalloc), Thrust's stable radix sort and reductions.
// No atomic operations: every value is written by one thread (the walls' reactions per grain,
// summed by a reduction), so a run is reproducible bit for bit.
#include <cuda_runtime.h>
#include <thrust/device_ptr.h>
#include <thrust/execution_policy.h>
#include <thrust/reduce.h>
#include <thrust/sort.h>

#include "gpu/engine.hpp"

namespace gf::gpu {

namespace detail {

namespace {

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess)
    throw Error(fmt::format("CUDA: {} failed: {}", what, cudaGetErrorString(e)));
}

constexpr int kBlock = 128;
int blocks(int n) {
  return (n + kBlock - 1) / kBlock;
}

__global__ void drift_kernel(Grains g, Domain dom, double dt, Vec3 gravity, double half_skin2,
                             int* flag) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.n) drift_one(i, g, dom, dt, gravity, half_skin2, flag);
}
__global__ void place_kernel(Grains g, const PlacedMotion* motions, Domain dom, double half_skin2,
                             int* flag) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.n) place_one(i, g, motions, dom, half_skin2, flag);
}
__global__ void kick_kernel(Grains g, double dt) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.n) kick_one(i, g, dt);
}
__global__ void cell_kernel(Grains g, Cells c) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.n) cell_one(i, g, c);
}
__global__ void range_kernel(int n, Cells c) {
  const int s = blockIdx.x * blockDim.x + threadIdx.x;
  if (s < n) range_one(s, n, c);
}
__global__ void list_kernel(Grains g, Domain dom, Cells c, double skin, List l, List old) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.n) list_one(i, g, dom, c, skin, l, old);
}
__global__ void force_kernel(Grains g, List l, Walls w, Laws law, Domain dom, double dt, double t,
                             int* touching, int* wall_touching) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.n) force_one(i, g, l, w, law, dom, dt, t, touching, wall_touching);
}
template <class T>
__global__ void fill_kernel(T* p, std::size_t n, T value) {
  const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) p[i] = value;
}

struct IntMax {
  __host__ __device__ int operator()(int a, int b) const { return a > b ? a : b; }
};
struct VecPlus {
  __host__ __device__ Vec3 operator()(const Vec3& a, const Vec3& b) const { return a + b; }
};

}  // namespace

struct CudaExec {
  template <class T>
  struct Array {
    T* ptr = nullptr;
    std::size_t size = 0;
    Array() = default;
    Array(const Array&) = delete;
    Array& operator=(const Array&) = delete;
    ~Array() { cudaFree(ptr); }
    void resize(std::size_t n) {
      if (n == size) return;
      cudaFree(ptr);
      ptr = nullptr;
      size = 0;
      if (n > 0) check(cudaMalloc(&ptr, n * sizeof(T)), "cudaMalloc");
      size = n;
    }
    void upload(const T* host, std::size_t n) {
      resize(n);
      if (n > 0) check(cudaMemcpy(ptr, host, n * sizeof(T), cudaMemcpyHostToDevice), "upload");
    }
    void download(T* host, std::size_t n) const {
      if (n > 0) check(cudaMemcpy(host, ptr, n * sizeof(T), cudaMemcpyDeviceToHost), "download");
    }
    void zero() {
      if (size > 0) check(cudaMemset(ptr, 0, size * sizeof(T)), "cudaMemset");
    }
    void fill(const T& value) {
      if (size == 0) return;
      const int nb = static_cast<int>((size + kBlock - 1) / kBlock);
      fill_kernel<<<nb, kBlock>>>(ptr, size, value);
      check(cudaGetLastError(), "fill kernel");
    }
  };
  static void drift(const Grains& g, const Domain& dom, double dt, const Vec3& gravity,
                    double half_skin2, int* flag) {
    drift_kernel<<<blocks(g.n), kBlock>>>(g, dom, dt, gravity, half_skin2, flag);
    check(cudaGetLastError(), "drift kernel");
  }
  static void place(const Grains& g, const PlacedMotion* motions, const Domain& dom,
                    double half_skin2, int* flag) {
    place_kernel<<<blocks(g.n), kBlock>>>(g, motions, dom, half_skin2, flag);
    check(cudaGetLastError(), "place kernel");
  }
  static void kick(const Grains& g, double dt) {
    kick_kernel<<<blocks(g.n), kBlock>>>(g, dt);
    check(cudaGetLastError(), "kick kernel");
  }
  static void cells(const Grains& g, const Cells& c) {
    cell_kernel<<<blocks(g.n), kBlock>>>(g, c);
    check(cudaGetLastError(), "cell kernel");
  }
  static void ranges(int n, const Cells& c) {
    range_kernel<<<blocks(n), kBlock>>>(n, c);
    check(cudaGetLastError(), "range kernel");
  }
  static void list(const Grains& g, const Domain& dom, const Cells& c, double skin, const List& l,
                   const List& old) {
    list_kernel<<<blocks(g.n), kBlock>>>(g, dom, c, skin, l, old);
    check(cudaGetLastError(), "list kernel");
  }
  static void force(const Grains& g, const List& l, const Walls& w, const Laws& law,
                    const Domain& dom, double dt, double t, int* touching, int* wall_touching) {
    force_kernel<<<blocks(g.n), kBlock>>>(g, l, w, law, dom, dt, t, touching, wall_touching);
    check(cudaGetLastError(), "force kernel");
  }
  static void sort_by_key(int* key, int* val, int n) {
    thrust::stable_sort_by_key(thrust::device, key, key + n, val);
  }
  static int max(const int* a, int n) {
    const thrust::device_ptr<const int> p(a);
    return thrust::reduce(p, p + n, 0, IntMax{});
  }
  static std::int64_t sum(const int* a, int n) {
    const thrust::device_ptr<const int> p(a);
    return thrust::reduce(p, p + n, std::int64_t{0});
  }
  static Vec3 sum(const Vec3* a, int n) {
    const thrust::device_ptr<const Vec3> p(a);
    return thrust::reduce(p, p + n, Vec3{}, VecPlus{});
  }
  template <class T>
  static void copy(T* dst, const T* src, std::size_t n) {
    check(cudaMemcpy(dst, src, n * sizeof(T), cudaMemcpyDeviceToDevice), "copy");
  }
  template <class T>
  static T read(const T* p) {
    T v;
    check(cudaMemcpy(&v, p, sizeof(T), cudaMemcpyDeviceToHost), "read");
    return v;
  }
  template <class T>
  static void write(T* p, T value) {
    check(cudaMemcpy(p, &value, sizeof(T), cudaMemcpyHostToDevice), "write");
  }
  static void sync() { check(cudaDeviceSynchronize(), "a time step"); }
};

std::unique_ptr<EngineBase> make_cuda_engine(const ParticleStore& p, const SphereDemSetup& s) {
  return std::make_unique<Engine<CudaExec>>(p, s);
}

}  // namespace detail

bool cuda_built() {
  return true;
}

bool device_available(std::string* why) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess || n == 0) {
    if (why)
      *why = e != cudaSuccess ? fmt::format("no usable CUDA device ({})", cudaGetErrorString(e))
                              : std::string("no CUDA device");
    return false;
  }
  return true;
}

}  // namespace gf::gpu
