// SPDX-License-Identifier: GPL-3.0-or-later
// Reading the parts the continuum methods' blocks share.
#include "io/input/continuum_input.hpp"

#include <fmt/format.h>

#include "core/error.hpp"

namespace gf::input {

namespace {

template <class Infos>
std::vector<std::string> keys_of(const Infos& infos) {
  std::vector<std::string> keys;
  for (const auto& i : infos) keys.emplace_back(i.key);
  return keys;
}

}  // namespace

KtgfInput read_ktgf_input(const YamlNode& block, const std::vector<std::string>& extra,
                          const std::string& default_dense, bool allow_none) {
  KtgfInput r;
  std::vector<std::string> accepted{"closures", "radial_distribution", "dense"};
  accepted.insert(accepted.end(), extra.begin(), extra.end());
  YamlMap k(block);
  r.closures = k.has("closures") ? k.string("closures") : "lun";
  r.radial = k.has("radial_distribution") ? k.string("radial_distribution") : "carnahan_starling";
  const auto* set = continuum::find_ktgf_closure(r.closures);
  if (!set)
    k.at("closures")
        .fail_expected("a KTGF closure set: " + join(keys_of(continuum::ktgf_closure_infos())));
  const auto* radial = continuum::find_radial_distribution(r.radial);
  if (!radial)
    k.at("radial_distribution")
        .fail_expected("a radial distribution: " +
                       join(keys_of(continuum::radial_distribution_infos())));
  std::vector<ParamSpec> schema(set->params.begin(), set->params.end());
  schema.insert(schema.end(), radial->params.begin(), radial->params.end());
  for (const auto& p : schema) accepted.emplace_back(p.name);
  k.check_keys(accepted, fmt::format("keys of kinetic_theory (closures '{}', radial "
                                     "distribution '{}')",
                                     r.closures, r.radial));
  r.params = read_schema_params(k, block, schema, fmt::format("KTGF closure set '{}'", r.closures));
  try {
    r.ktgf = continuum::prepare_ktgf(r.closures, r.params, r.radial);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    block.fail(e.what());
  }
  r.dense = default_dense;
  std::optional<YamlNode> dn = k.find("dense");
  std::optional<YamlMap> d;
  if (dn) {
    if (allow_none && dn->is_scalar()) {
      dn->as_choice({"none"});
      r.dense = "none";
      return r;
    }
    d.emplace(*dn);
    r.dense = d->string("model");
  }
  const auto* dense = continuum::find_frictional_model(r.dense);
  if (!dense)
    d->at("model").fail_expected(
        "a dense-regime model: " + join(keys_of(continuum::frictional_model_infos())) +
        (allow_none ? " (or dense: none)" : ""));
  if (d) {
    std::vector<std::string> dk{"model"};
    for (const auto& p : dense->params) dk.emplace_back(p.name);
    d->check_keys(dk, fmt::format("parameters of dense-regime model '{}'", r.dense));
    r.dense_params = read_schema_params(*d, *dn, {dense->params.begin(), dense->params.end()},
                                        fmt::format("dense-regime model '{}'", r.dense));
  }
  try {
    r.frictional = continuum::prepare_frictional(r.dense, r.dense_params);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    (dn ? *dn : block).fail(e.what());
  }
  return r;
}

OutputSchedule read_output_schedule(const YamlNode& node) {
  YamlMap o(node, {"vtk_every", "series_every", "checkpoint_every"});
  OutputSchedule s;
  s.vtk_every = o.number_or("vtk_every", 0.0, Range::non_negative());
  s.series_every = o.number_or("series_every", 0.0, Range::non_negative());
  s.checkpoint_every = o.number_or("checkpoint_every", 0.0, Range::non_negative());
  return s;
}

}  // namespace gf::input
