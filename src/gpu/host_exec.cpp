// SPDX-License-Identifier: GPL-3.0-or-later
// The host mirror of the device step: the bodies of kernels.hpp in plain loops over the grains,
// in index order (one "thread" after another), over std::vector arrays.
#include <algorithm>
#include <numeric>

#include "gpu/engine.hpp"

namespace gf::gpu::detail {

struct HostExec {
  template <class T>
  struct Array {
    T* ptr = nullptr;
    std::size_t size = 0;
    std::vector<T> data;
    Array() = default;
    Array(const Array&) = delete;  // (as the device's: a copy would alias the data)
    Array& operator=(const Array&) = delete;
    void resize(std::size_t n) {
      data.resize(n);
      size = n;
      ptr = data.data();
    }
    void upload(const T* host, std::size_t n) {
      resize(n);
      std::copy(host, host + n, data.begin());
    }
    void download(T* host, std::size_t n) const { std::copy(data.begin(), data.begin() + n, host); }
    void zero() { std::fill(data.begin(), data.end(), T{}); }
    void fill(const T& value) { std::fill(data.begin(), data.end(), value); }
  };
  static void drift(const Grains& g, const Domain& dom, double dt, const Vec3& gravity,
                    double half_skin2, int* flag) {
    for (int i = 0; i < g.n; ++i) drift_one(i, g, dom, dt, gravity, half_skin2, flag);
  }
  static void place(const Grains& g, const PlacedMotion* motions, const Domain& dom,
                    double half_skin2, int* flag) {
    for (int i = 0; i < g.n; ++i) place_one(i, g, motions, dom, half_skin2, flag);
  }
  static void kick(const Grains& g, double dt) {
    for (int i = 0; i < g.n; ++i) kick_one(i, g, dt);
  }
  static void cells(const Grains& g, const Cells& c) {
    for (int i = 0; i < g.n; ++i) cell_one(i, g, c);
  }
  static void ranges(int n, const Cells& c) {
    for (int s = 0; s < n; ++s) range_one(s, n, c);
  }
  static void list(const Grains& g, const Domain& dom, const Cells& c, double skin, const List& l,
                   const List& old) {
    for (int i = 0; i < g.n; ++i) list_one(i, g, dom, c, skin, l, old);
  }
  static void force(const Grains& g, const List& l, const Walls& w, const Laws& law,
                    const Domain& dom, double dt, double t, int* touching, int* wall_touching) {
    for (int i = 0; i < g.n; ++i) force_one(i, g, l, w, law, dom, dt, t, touching, wall_touching);
  }
  static void sort_by_key(int* key, int* val, int n) {
    std::vector<std::pair<int, int>> kv(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) kv[static_cast<std::size_t>(i)] = {key[i], val[i]};
    std::stable_sort(kv.begin(), kv.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (int i = 0; i < n; ++i) {
      key[i] = kv[static_cast<std::size_t>(i)].first;
      val[i] = kv[static_cast<std::size_t>(i)].second;
    }
  }
  static int max(const int* a, int n) { return n > 0 ? *std::max_element(a, a + n) : 0; }
  static std::int64_t sum(const int* a, int n) {
    return std::accumulate(a, a + n, std::int64_t{0});
  }
  static Vec3 sum(const Vec3* a, int n) { return std::accumulate(a, a + n, Vec3{}); }
  template <class T>
  static void copy(T* dst, const T* src, std::size_t n) {
    std::copy(src, src + n, dst);
  }
  template <class T>
  static T read(const T* p) {
    return *p;
  }
  template <class T>
  static void write(T* p, T value) {
    *p = value;
  }
  static void sync() {}
};

std::unique_ptr<EngineBase> make_host_engine(const ParticleStore& p, const SphereDemSetup& s) {
  return std::make_unique<Engine<HostExec>>(p, s);
}

}  // namespace gf::gpu::detail
