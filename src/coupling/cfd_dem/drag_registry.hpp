// SPDX-License-Identifier: GPL-3.0-or-later
// The one list of drag laws. Name lookup, list-models, describe, input validation and the
// per-particle dispatch (a switch, no virtual call) all derive from `DragLaws`.
#pragma once

#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/registry.hpp"
#include "coupling/cfd_dem/drag_laws.hpp"

namespace gf::cfd_dem {

using DragLaws = TypeList<SchillerNaumann, DiFelice, WenYu, Gidaspow, Beetstra, HolzerSommerfeld>;

/// Description of a registered drag law, for the command line, the docs and the input reader.
struct DragInfo {
  std::string_view key, summary, equation, reference, validity;
  std::span<const ParamSpec> params;
};

/// Every law of DragLaws, in list order.
std::vector<DragInfo> drag_infos();
/// Index in DragLaws, or -1.
int drag_index(std::string_view key);
/// The law's description, or nullptr for an unknown key.
const DragInfo* find_drag(std::string_view key);

/// Checks the parameters of law `key` against its schema (unknown name or value out of range:
/// gf::Error naming both) and derives the constants the particle loop reads; defaults fill
/// what is not given.
DragParams prepare_drag(std::string_view key, const std::map<std::string, double>& params = {});

/// Drag on one particle by the law at index `law` of DragLaws (p.law is not read, so one
/// DragParams may serve a loop that picks the law per particle type).
inline DragOutput drag_force(int law, const DragInput& in, const DragParams& p) {
  return dispatch_index(DragLaws{}, law, [&]<class L>() { return L::eval(in, p); });
}

}  // namespace gf::cfd_dem
