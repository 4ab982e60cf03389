// SPDX-License-Identifier: GPL-3.0-or-later
// Registry functions generated from the HeatTransferLaws list.
#include "coupling/cfd_dem/heat_transfer.hpp"

namespace gf::cfd_dem {

std::vector<HeatTransferInfo> heat_transfer_infos() {
  std::vector<HeatTransferInfo> out;
  for_each_type(HeatTransferLaws{}, [&]<class L>() {
    out.push_back({L::key, L::summary, L::equation, L::reference, L::validity});
  });
  return out;
}

int heat_transfer_index(std::string_view key) {
  return index_of_key(HeatTransferLaws{}, key);
}

const HeatTransferInfo* find_heat_transfer(std::string_view key) {
  static const std::vector<HeatTransferInfo> infos = heat_transfer_infos();
  const int i = heat_transfer_index(key);
  return i < 0 ? nullptr : &infos[static_cast<std::size_t>(i)];
}

}  // namespace gf::cfd_dem
