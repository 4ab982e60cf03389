// SPDX-License-Identifier: GPL-3.0-or-later
// Neighbour-list statistics of a grainflow checkpoint (list entries, touching pairs, non-zero
// histories per particle), for the bytes-per-particle-step estimate in bench/PROFILE.md.
// Built by build.sh (plain HDF5 C API), not part of the CMake build.
#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

template <class T>
std::vector<T> read(hid_t f, const char* name, hid_t type, std::size_t per_item) {
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) {
    std::fprintf(stderr, "no dataset %s\n", name);
    std::exit(1);
  }
  const hid_t s = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  std::vector<T> out(static_cast<std::size_t>(n));
  H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(s);
  H5Dclose(d);
  (void)per_item;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: list_stats checkpoint.h5\n");
    return 2;
  }
  const hid_t f = H5Fopen(argv[1], H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return 1;
  const auto x = read<double>(f, "particles/position", H5T_NATIVE_DOUBLE, 3);
  const auto r = read<double>(f, "particles/radius", H5T_NATIVE_DOUBLE, 1);
  const auto off = read<std::int64_t>(f, "neighbor/offsets", H5T_NATIVE_INT64, 1);
  const auto nb = read<std::int32_t>(f, "neighbor/neighbors", H5T_NATIVE_INT32, 1);
  const auto h = read<double>(f, "neighbor/history", H5T_NATIVE_DOUBLE, 3);
  const auto wp = read<std::int32_t>(f, "walls/contact_particle", H5T_NATIVE_INT32, 1);
  H5Fclose(f);
  const std::size_t n = r.size();
  std::size_t touching = 0, hist_nonzero = 0, hist_nonzero_apart = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::size_t j = static_cast<std::size_t>(nb[static_cast<std::size_t>(k)]);
      double d2 = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = x[3 * i + c] - x[3 * j + c];
        d2 += d * d;
      }
      const double rs = r[i] + r[j];
      const bool t = d2 < rs * rs;
      const bool hz = h[3 * k] != 0 || h[3 * k + 1] != 0 || h[3 * k + 2] != 0;
      touching += t;
      hist_nonzero += hz;
      hist_nonzero_apart += hz && !t;
    }
  const double entries = static_cast<double>(nb.size());
  std::printf("particles            %zu\n", n);
  std::printf("list entries         %.0f  (%.3f per particle, half list)\n", entries, entries / n);
  std::printf("touching pairs       %zu  (%.3f per particle, coordination %.3f)\n", touching,
              double(touching) / n, 2.0 * touching / n);
  std::printf("non-zero histories   %zu  (apart but non-zero: %zu)\n", hist_nonzero,
              hist_nonzero_apart);
  std::printf("touching / entries   %.3f\n", touching / entries);
  std::printf("wall-list entries    %zu  (%.3f per particle)\n", wp.size(), double(wp.size()) / n);
  return 0;
}
