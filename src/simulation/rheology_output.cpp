// SPDX-License-Identifier: GPL-3.0-or-later
// Rheology samples, steady-state averages (MSER-5 truncation, block-averaged standard errors)
// and the kinetic-theory comparison.
#include "simulation/rheology_output.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "analysis/kinetic_theory.hpp"
#include "analysis/steady_stats.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "io/input/validate.hpp"
#include "simulation/simulation.hpp"

namespace gf {

namespace {

/// The series that choose the steady window (MSER) and are checked for drift.
constexpr const char* kKeyQuantities[] = {"granular_temperature", "pressure", "sigma_xz"};

/// The columns of rheology.csv after time and strain: the layer's measurements
/// (analysis::rheology_columns) and the shear walls' tractions.
const std::vector<std::string>& sample_columns() {
  static const std::vector<std::string> cols = [] {
    auto c = analysis::rheology_columns();
    c.insert(c.end(), {"wall_sigma_xz", "wall_sigma_zz"});
    return c;
  }();
  return cols;
}

std::size_t column_index(const std::string& name) {
  const auto& cols = sample_columns();
  for (std::size_t k = 0; k < cols.size(); ++k)
    if (cols[k] == name) return k;
  return cols.size();
}

/// The traction of the shear walls (shear.boundary: walls) on the grains' momentum, averaged
/// over the steps since the previous sample and over the two walls, in the layer's convention
/// (compressive positive; sigma_xz of the sign of the layer's): {sigma_xz, sigma_zz} =
/// (F_top - F_bottom)_{x, z} / (2 A), F the force of the grains on a wall, A = L_x L_y. NaN
/// without those walls (Lees-Edwards) or in 2D.
std::array<double, 2> shear_wall_traction(const Simulation& sim) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto& walls = sim.walls();
  std::optional<std::size_t> top, bottom;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    if (walls[k].name == "shear_top") top = k;
    if (walls[k].name == "shear_bottom") bottom = k;
  }
  if (!top || !bottom || sim.config().dimension != 3) return {nan, nan};
  const Vec3 l = sim.domain().length();
  const double area = l.x * l.y;
  const Vec3 ft = sim.wall_mean_force(Simulation::WallMeans::Rheology, *top);
  const Vec3 fb = sim.wall_mean_force(Simulation::WallMeans::Rheology, *bottom);
  return {(ft.x - fb.x) / (2 * area), (ft.z - fb.z) / (2 * area)};
}

/// Restitution of the first particle group's material with itself (NaN if not given).
double grain_restitution(const config::Case& c) {
  if (c.particles.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::string& m = c.particles.front().material;
  for (const auto& ct : c.contacts)
    if (ct.between[0] == m && ct.between[1] == m) {
      const auto it = ct.params.find("restitution");
      if (it != ct.params.end()) return it->second;
    }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::map<std::string, std::array<double, 3>> read_rheology_summary(
    const std::filesystem::path& file) {
  std::map<std::string, std::array<double, 3>> out;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string field[4];
    for (auto& f : field) std::getline(ss, f, ',');
    std::array<double, 3> v{};
    for (int k = 0; k < 3; ++k) {
      try {
        v[static_cast<std::size_t>(k)] = std::stod(field[k + 1]);
      } catch (const std::exception&) {
        v[static_cast<std::size_t>(k)] = std::nan("");
      }
    }
    out[field[0]] = v;
  }
  return out;
}

const RheologySummaryRow* RheologySummary::find(const std::string& q) const {
  for (const auto& r : rows)
    if (r.quantity == q) return &r;
  return nullptr;
}

RheologyOutput::RheologyOutput(const std::filesystem::path& dir, const Simulation& sim,
                               std::optional<double> continue_at)
    : dir_(dir) {
  const auto& r = *sim.config().analysis.rheology;
  every_ = std::max<std::int64_t>(1, std::llround(r.every / sim.dt()));
  std::vector<std::string> cols{"strain"};
  for (const auto& c : sample_columns()) cols.push_back(c);
  values_.resize(sample_columns().size());
  if (!continue_at) {
    csv_ = std::make_unique<io::SeriesCsv>(dir / "rheology.csv", cols);
    return;
  }
  // The sample at the checkpoint's step, if one was taken, was taken before it: keep it.
  csv_ = std::make_unique<io::SeriesCsv>(dir / "rheology.csv", cols,
                                         io::SeriesContinuation{*continue_at, true});
  for (const auto& row : csv_->kept_rows()) {  // time, strain, then the rheology columns
    times_.push_back(row[0]);
    for (std::size_t k = 0; k < values_.size(); ++k) values_[k].push_back(row[k + 2]);
  }
}

void RheologyOutput::sample(const Simulation& sim) {
  const analysis::RheologySample s = sim.rheology_sample();
  auto v = analysis::rheology_values(s);
  const auto traction = shear_wall_traction(sim);
  v.insert(v.end(), traction.begin(), traction.end());
  const auto& shear = sim.config().shear;
  std::vector<double> row{shear ? shear->rate * sim.time() : 0.0};
  row.insert(row.end(), v.begin(), v.end());
  csv_->append(sim.time(), row);
  times_.push_back(sim.time());
  for (std::size_t k = 0; k < v.size(); ++k) values_[k].push_back(v[k]);
}

void RheologyOutput::contact_weighted_fabric(std::size_t start,
                                             std::vector<RheologySummaryRow>& rows) const {
  // The fabric is a mean over contacts: samples weigh by their contacts C = Z N / 2 (a dilute
  // layer's samples often have none, and their zero fabric must not count).
  const std::size_t n = times_.size() - start;
  auto column = [&](const char* q) {
    return std::span<const double>(values_[column_index(q)]).subspan(start);
  };
  const auto z = column("coordination_number"), grains = column("grains");
  std::vector<double> w(n);
  for (std::size_t k = 0; k < n; ++k) w[k] = 0.5 * z[k] * grains[k];
  const char* comp[] = {"F_xx", "F_zz", "F_xz", "F_yy"};
  double mean[4];
  for (int c = 0; c < 4; ++c) {
    const auto a = analysis::weighted_block_average(column(comp[c]), w);
    mean[c] = a.mean;
    rows[column_index(comp[c])] = {comp[c], a.mean, a.std_error, std::nan("")};
  }
  // The angle of the mean fabric's major axis, theta = 1/2 atan2(b, a) with a = F_xx - F_zz,
  // b = 2 F_xz; its error from the samples' linearised deviations (the delta method).
  const double a = mean[0] - mean[1], b = 2 * mean[2], r2 = a * a + b * b;
  const double deg = 180.0 / std::numbers::pi;
  std::vector<double> lin(n);
  const auto fxx = column("F_xx"), fzz = column("F_zz"), fxz = column("F_xz");
  for (std::size_t k = 0; k < n; ++k)
    lin[k] = 0.5 * deg *
             (a * 2 * (fxz[k] - mean[2]) - b * ((fxx[k] - mean[0]) - (fzz[k] - mean[1]))) / r2;
  const auto angle = analysis::weighted_block_average(lin, w);
  rows[column_index("fabric_angle")] = {"fabric_angle", 0.5 * deg * std::atan2(b, a),
                                        r2 > 0 ? angle.std_error : std::nan(""), std::nan("")};
}

RheologySummary RheologyOutput::finish(const Simulation& sim) {
  csv_->flush();
  RheologySummary out;
  const auto& cfg = sim.config();
  const auto& cols = sample_columns();
  if (times_.size() < 2) return out;
  // One steady window for every quantity: the latest MSER-5 truncation of the key series, or
  // the first sample at or after analysis.rheology.start.
  std::size_t start = 0;
  if (cfg.analysis.rheology->start) {
    while (start < times_.size() && times_[start] < *cfg.analysis.rheology->start) ++start;
  } else {
    std::vector<std::span<const double>> key;
    for (const char* q : kKeyQuantities) key.emplace_back(values_[column_index(q)]);
    start = analysis::common_truncation(key);
  }
  if (start + 2 > times_.size()) start = times_.size() - 2;
  out.steady_start = times_[start];
  out.samples = times_.size() - start;

  // Steady averages of every column; the largest drift of the key ones.
  std::vector<RheologySummaryRow> rows;
  const char* drifting = nullptr;  // the key quantity with the largest |drift|
  if (out.samples < 4) out.drift = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t k = 0; k < cols.size(); ++k) {
    // A run continued with --append from an earlier build's series has nan in the columns that
    // build did not write: such a column averages its samples from the first one it has.
    std::size_t from = start;
    while (from < values_[k].size() && !std::isfinite(values_[k][from])) ++from;
    const auto a = analysis::steady_average(values_[k], from);
    rows.push_back({cols[k], a.avg.mean, a.avg.std_error, std::nan("")});
    for (const char* q : kKeyQuantities)
      if (cols[k] == q && std::abs(a.drift) > std::abs(out.drift)) {
        out.drift = a.drift;
        drifting = q;
      }
  }
  contact_weighted_fabric(start, rows);
  // Kinetic theory for volume-equivalent spheres at the measured volume fraction and rate.
  const double e = grain_restitution(cfg);
  const double phi = rows[column_index("volume_fraction")].mean;
  const double rate = rows[column_index("shear_rate")].mean;
  if (!cfg.particles.empty() && e > 0 && e < 1 && phi > 0 && phi < 0.6 && rate != 0) {
    const auto& g = cfg.particles.front();
    double rho = 0;
    for (const auto& m : cfg.materials)
      if (m.name == g.material) rho = m.density;
    const double d =
        analysis::volume_equivalent_diameter(input::grain_measure(g, g.radius.largest()));
    const auto p = analysis::lun_simple_shear(phi, e, d, rho, std::abs(rate));
    const std::pair<const char*, double> pred[] = {{"granular_temperature", p.temperature},
                                                   {"pressure", p.pressure},
                                                   {"pressure_streaming", p.pressure_streaming},
                                                   {"pressure_collisional", p.pressure_collisional},
                                                   {"sigma_xz", p.shear_stress},
                                                   {"sigma_s_xz", p.shear_stress_streaming},
                                                   {"sigma_c_xz", p.shear_stress_collisional},
                                                   {"sigma_xx", p.pressure},
                                                   {"sigma_yy", p.pressure},
                                                   {"sigma_zz", p.pressure},
                                                   {"friction", p.friction},
                                                   {"viscosity", p.viscosity},
                                                   {"N1", 0.0},
                                                   {"N2", 0.0},
                                                   {"N1_collisional", 0.0},
                                                   {"N2_collisional", 0.0}};
    for (const auto& [q, val] : pred) rows[column_index(q)].kinetic_theory = val;
  }
  out.rows = std::move(rows);

  write_atomically(dir_ / "rheology_summary.csv", [&](std::ostream& o) {
    o << "quantity,mean,std_error,kinetic_theory\n";
    o << fmt::format("steady_start_time,{:.10g},0,nan\n", out.steady_start);
    o << fmt::format("samples,{},0,nan\n", out.samples);
    o << fmt::format("steady_drift,{:.4g},0,nan\n", out.drift);
    for (const auto& r : out.rows)
      o << fmt::format("{},{:.10g},{:.10g},{:.10g}\n", r.quantity, r.mean, r.std_error,
                       r.kinetic_theory);
  });
  log::info(
      "rheology: steady state from t = {:.4g} s ({} samples); mean +- standard error, "
      "kinetic theory (Lun et al. 1984, volume-equivalent spheres):",
      out.steady_start, out.samples);
  // Momentum balance: in a steady shear flow between walls sigma_xz and sigma_zz are uniform
  // across the gap, so the layer's equal the walls' tractions. A difference beyond 3 combined
  // standard errors means the flow is not steady (a transient, e.g. walls that slip and cannot
  // sustain the initial shear) even when the series look flat. With a fluid the grains' stress
  // also exchanges momentum with the fluid by drag between the walls and the layer (slip at the
  // walls): no check there.
  for (const auto& [q, w] :
       {std::pair{"sigma_xz", "wall_sigma_xz"}, {"sigma_zz", "wall_sigma_zz"}}) {
    if (cfg.fluid) break;
    const auto* a = out.find(q);
    const auto* b = out.find(w);
    if (!a || !b || !std::isfinite(b->mean)) continue;
    const double err = std::hypot(a->std_error, b->std_error);
    if (err > 0 && std::abs(a->mean - b->mean) > 3 * err)
      log::warn(
          "rheology: the layer's {} ({:.4g} +- {:.2g} Pa) differs from the shear walls' traction "
          "({:.4g} +- {:.2g} Pa) by {:.1f} standard errors: momentum is not balanced, the flow is "
          "not steady (a transient, or walls that slip and cannot sustain the shear); run longer "
          "or set analysis.rheology.start",
          q, a->mean, a->std_error, b->mean, b->std_error, std::abs(a->mean - b->mean) / err);
  }
  if (drifting && std::abs(out.drift) > 3)
    log::warn(
        "rheology: {} drifts over the averaging window ({:+.1f} standard errors between its "
        "halves; steady runs exceed 3 in a few % of cases): the averages are likely not "
        "steady; run longer (shear.strain) or set analysis.rheology.start",
        drifting, out.drift);
  for (const char* q :
       {"volume_fraction", "shear_rate", "granular_temperature", "pressure", "sigma_xz",
        "wall_sigma_xz", "sigma_zz", "wall_sigma_zz", "friction", "N1", "N2", "alignment_angle"}) {
    const auto* r = out.find(q);
    if (q[0] == 'w' && !std::isfinite(r->mean)) continue;  // no shear walls
    log::info("  {:<22} {:12.5g} +- {:<10.3g} {}", q, r->mean, r->std_error,
              std::isnan(r->kinetic_theory) ? std::string("")
                                            : fmt::format("KT {:.5g}", r->kinetic_theory));
  }
  return out;
}

}  // namespace gf
