// SPDX-License-Identifier: GPL-3.0-or-later
// Whole-case checks: materials and pairs, particles in the domain, overlaps, time step limits.
#include "io/input/validate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "contact/registry.hpp"
#include "core/error.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

std::string vec_text(const Vec3& v) {
  return fmt::format("[{}, {}, {}]", number_text(v.x), number_text(v.y), number_text(v.z));
}

std::string seconds(double t) {
  return fmt::format("{:.4g} s", t);
}

/// Smallest and largest radius of the grains of one material.
struct GrainSizes {
  double r_min = inf;
  double r_max = 0;
};

/// One explicit particle, for the domain and overlap checks.
struct Placed {
  Vec3 x;
  double r;
  std::size_t group;
  std::size_t index;
};

class Validator {
 public:
  explicit Validator(const config::Case& c) : c_(c) {}
  CheckReport run();

 private:
  config::SourceLoc at(config::SourceLoc loc, const std::string& fallback_path) const {
    if (loc.file.empty()) loc.file = c_.file.string();
    if (loc.key_path.empty()) loc.key_path = fallback_path;
    return loc;
  }
  config::SourceLoc group_loc(std::size_t g) const {
    return at(c_.particles[g].loc, fmt::format("particles[{}]", g));
  }
  config::SourceLoc particle_loc(std::size_t g, std::size_t i) const;

  void check_basics() const;
  void check_materials();
  void check_fills();
  void check_explicit();
  void check_overlaps(const std::vector<Placed>& all) const;
  void check_periodic() const;
  void estimate_counts();
  void check_time_step();
  void check_output();

  const config::Case& c_;
  CheckReport report_;
  std::map<std::string, const config::Material*> materials_;
  std::map<std::string, GrainSizes> grains_;     ///< particle materials only
  std::vector<std::string> particle_materials_;  ///< in order of first use
  std::map<std::pair<std::string, std::string>, const config::Contact*> contacts_;
  std::vector<Placed> placed_;
};

config::SourceLoc Validator::particle_loc(std::size_t g, std::size_t i) const {
  const auto& group = c_.particles[g];
  const auto& ex = *group.explicit_particles;
  config::SourceLoc loc = group_loc(g);
  loc.column = 0;
  loc.line = i < ex.lines.size() ? ex.lines[i] : 0;
  if (!ex.file.empty()) {
    loc.file = ex.file.string();
    loc.key_path += ".file";
  } else {
    loc.key_path += fmt::format(".positions[{}]", i);
  }
  if (loc.line == 0) loc = group_loc(g);
  return loc;
}

void Validator::check_basics() const {
  if (!(c_.time.step > 0) || !(c_.time.end >= c_.time.step))
    throw_input_error(at(c_.time.loc, "time.step"),
                      "expected time.step > 0 and time.end >= time.step");
  for (int k = 0; k < 3; ++k)
    if (!(c_.domain.max[k] > c_.domain.min[k]))
      throw_input_error(at(c_.domain.loc, "domain"),
                        "expected domain.max > domain.min in every component");
  if (c_.particles.empty())
    throw_input_error(at({}, "particles"), "expected at least one particle group");
}

void Validator::check_materials() {
  for (const auto& m : c_.materials) materials_[m.name] = &m;
  auto need = [&](const std::string& name, const config::SourceLoc& loc) {
    if (!materials_.count(name)) throw_input_error(loc, fmt::format("unknown material '{}'", name));
  };
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    need(group.material, group_loc(g));
    auto& gs = grains_[group.material];
    if (std::find(particle_materials_.begin(), particle_materials_.end(), group.material) ==
        particle_materials_.end())
      particle_materials_.push_back(group.material);
    if (group.explicit_particles && !group.explicit_particles->radii.empty()) {
      const auto& r = group.explicit_particles->radii;
      gs.r_min = std::min(gs.r_min, *std::min_element(r.begin(), r.end()));
      gs.r_max = std::max(gs.r_max, *std::max_element(r.begin(), r.end()));
    } else {
      if (!(group.radius.smallest() > 0)) throw_input_error(group_loc(g), "expected a radius > 0");
      gs.r_min = std::min(gs.r_min, group.radius.smallest());
      gs.r_max = std::max(gs.r_max, group.radius.largest());
    }
  }
  for (std::size_t w = 0; w < c_.walls.size(); ++w)
    need(c_.walls[w].material, at(c_.walls[w].loc, fmt::format("walls[{}]", w)));
  for (std::size_t i = 0; i < c_.contacts.size(); ++i) {
    const auto& ct = c_.contacts[i];
    const auto loc = at(ct.loc, fmt::format("contacts[{}]", i));
    need(ct.between[0], loc);
    need(ct.between[1], loc);
    if (!contact::find_model(ct.model))
      throw_input_error(loc, fmt::format("unknown contact model '{}'", ct.model));
    contacts_[std::minmax(ct.between[0], ct.between[1])] = &ct;
  }
  auto need_pair = [&](const std::string& a, const std::string& b, const config::SourceLoc& loc) {
    if (!contacts_.count(std::minmax(a, b)))
      throw_input_error(loc, fmt::format("no contacts entry for the material pair ({}, {})",
                                         std::min(a, b), std::max(a, b)));
  };
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    for (std::size_t h = 0; h <= g; ++h)
      need_pair(c_.particles[h].material, c_.particles[g].material, group_loc(g));
    for (std::size_t w = 0; w < c_.walls.size(); ++w)
      need_pair(c_.particles[g].material, c_.walls[w].material,
                at(c_.walls[w].loc, fmt::format("walls[{}]", w)));
  }
}

void Validator::check_fills() {
  const Vec3 lo = c_.domain.min, hi = c_.domain.max;
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (!group.fill) continue;
    const auto& f = *group.fill;
    Vec3 flo, fhi;
    if (f.region.kind == config::Region::Kind::Box) {
      flo = f.region.min;
      fhi = f.region.max;
    } else {
      const Vec3 a = f.region.axis, e0 = f.region.center,
                 e1 = f.region.center + f.region.height * a;
      for (int k = 0; k < 3; ++k) {
        const double ext = f.region.radius * std::sqrt(std::max(0.0, 1 - a[k] * a[k]));
        flo[k] = std::min(e0[k], e1[k]) - ext;
        fhi[k] = std::max(e0[k], e1[k]) + ext;
      }
    }
    for (int k = 0; k < 3; ++k) {
      const double tol = 1e-9 * (hi[k] - lo[k]);
      if (flo[k] < lo[k] - tol || fhi[k] > hi[k] + tol) {
        config::SourceLoc loc = f.loc.line > 0 ? at(f.loc, "") : group_loc(g);
        if (loc.key_path.empty() || f.loc.line == 0)
          loc.key_path = fmt::format("particles[{}].fill", g);
        throw_input_error(
            loc, fmt::format("the fill region (bounds {} - {}) reaches outside the domain {} - {}",
                             vec_text(flo), vec_text(fhi), vec_text(lo), vec_text(hi)));
      }
    }
  }
}

void Validator::check_explicit() {
  const Vec3 lo = c_.domain.min, hi = c_.domain.max;
  std::size_t n_out = 0;
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (!group.explicit_particles) continue;
    const auto& ex = *group.explicit_particles;
    const std::size_t n = ex.positions.size();
    auto same_size = [&](std::size_t m, const char* what) {
      if (m != 0 && m != n)
        throw_input_error(group_loc(g),
                          fmt::format("expected {} {} (one per particle), found {}", n, what, m));
    };
    same_size(ex.velocities.size(), "velocities");
    same_size(ex.angular_velocities.size(), "angular velocities");
    same_size(ex.radii.size(), "radii");
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& x = ex.positions[i];
      const double r =
          ex.radii.empty() ? group.radius.largest() : ex.radii[i];  // as the simulation builds it
      for (int k = 0; k < 3; ++k) {
        if (!(x[k] >= lo[k] && x[k] <= hi[k]))
          throw_input_error(particle_loc(g, i),
                            fmt::format("particle {} at {} lies outside the domain {} - {}", i,
                                        vec_text(x), vec_text(lo), vec_text(hi)));
        if (!c_.domain.periodic[k] && (x[k] - r < lo[k] || x[k] + r > hi[k])) ++n_out;
      }
      placed_.push_back({x, r, g, i});
    }
  }
  if (n_out > 0)
    report_.warnings.push_back(
        fmt::format("{} explicit particle(s) stick out of the domain through a non-periodic face "
                    "(centre inside, surface outside)",
                    n_out));
}

void Validator::check_overlaps(const std::vector<Placed>& all) const {
  if (all.size() < 2) return;
  double r_max = 0;
  for (const auto& p : all) r_max = std::max(r_max, p.r);
  const double h = 2 * r_max;
  const Vec3 lo = c_.domain.min, len = c_.domain.max - c_.domain.min;
  std::int64_t n[3];
  double size[3];
  for (int k = 0; k < 3; ++k) {
    n[k] =
        std::clamp<std::int64_t>(static_cast<std::int64_t>(len[k] / h), 1, std::int64_t{1} << 20);
    size[k] = len[k] / static_cast<double>(n[k]);
  }
  auto cell_of = [&](const Vec3& x, std::int64_t ci[3]) {
    for (int k = 0; k < 3; ++k)
      ci[k] = std::clamp<std::int64_t>(static_cast<std::int64_t>((x[k] - lo[k]) / size[k]), 0,
                                       n[k] - 1);
  };
  auto id_of = [&](const std::int64_t ci[3]) { return (ci[0] * n[1] + ci[1]) * n[2] + ci[2]; };
  std::vector<std::pair<std::int64_t, std::size_t>> sorted(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::int64_t ci[3];
    cell_of(all[i].x, ci);
    sorted[i] = {id_of(ci), i};
  }
  std::sort(sorted.begin(), sorted.end());
  // Neighbouring cell indices along one axis (all cells when there are at most three).
  auto neighbours = [&](int k, std::int64_t c, std::int64_t out[3]) {
    int m = 0;
    if (n[k] <= 3) {
      for (std::int64_t j = 0; j < n[k]; ++j) out[m++] = j;
      return m;
    }
    for (std::int64_t d = -1; d <= 1; ++d) {
      std::int64_t j = c + d;
      if (j < 0 || j >= n[k]) {
        if (!c_.domain.periodic[k]) continue;
        j = (j + n[k]) % n[k];
      }
      out[m++] = j;
    }
    return m;
  };
  // The first particle (in input order) that overlaps an earlier one is reported.
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::int64_t ci[3], nb[3][3];
    int nn[3];
    cell_of(all[i].x, ci);
    for (int k = 0; k < 3; ++k) nn[k] = neighbours(k, ci[k], nb[k]);
    for (int a = 0; a < nn[0]; ++a)
      for (int b = 0; b < nn[1]; ++b)
        for (int d = 0; d < nn[2]; ++d) {
          const std::int64_t cj[3] = {nb[0][a], nb[1][b], nb[2][d]};
          const std::int64_t id = id_of(cj);
          auto range = std::equal_range(
              sorted.begin(), sorted.end(), std::pair<std::int64_t, std::size_t>{id, 0},
              [](const auto& p, const auto& q) { return p.first < q.first; });
          for (auto it = range.first; it != range.second; ++it) {
            const std::size_t j = it->second;
            if (j >= i) continue;
            Vec3 dx = all[i].x - all[j].x;
            for (int k = 0; k < 3; ++k) {
              if (!c_.domain.periodic[k]) continue;
              if (dx[k] > 0.5 * len[k])
                dx[k] -= len[k];
              else if (dx[k] < -0.5 * len[k])
                dx[k] += len[k];
            }
            const double reach = all[i].r + all[j].r;
            const double dist = norm(dx);
            if (dist < reach * (1 - 1e-9)) {
              const auto& p = all[i];
              const auto& q = all[j];
              throw_input_error(
                  particle_loc(p.group, p.index),
                  fmt::format(
                      "particle {} of particles[{}] at {} (radius {}) overlaps particle {} of "
                      "particles[{}] "
                      "at {} (radius {}){}: centre distance {:.6g} m < {:.6g} m",
                      p.index, p.group, vec_text(p.x), number_text(p.r), q.index, q.group,
                      vec_text(q.x), number_text(q.r),
                      q.index < c_.particles[q.group].explicit_particles->lines.size()
                          ? fmt::format(", line {}",
                                        c_.particles[q.group].explicit_particles->lines[q.index])
                          : std::string(),
                      dist, reach));
            }
          }
        }
  }
}

void Validator::check_periodic() const {
  double r_max = 0;
  for (const auto& [name, gs] : grains_) r_max = std::max(r_max, gs.r_max);
  const double skin = c_.neighbor.skin.value_or(0.5 * r_max);
  const double cutoff = 2 * r_max + skin;
  for (int k = 0; k < 3; ++k) {
    const double len = c_.domain.max[k] - c_.domain.min[k];
    if (c_.domain.periodic[k] && !(len > 2 * cutoff)) {
      config::SourceLoc loc = at(c_.domain.loc, "domain");
      loc.key_path = "domain.periodic";
      throw_input_error(
          loc, fmt::format("the periodic length along {} ({} m) must exceed twice the neighbour "
                           "cut-off 2 (2 r_max + skin) = {} m, so that a grain meets one image of "
                           "another at most",
                           "xyz"[k], number_text(len), number_text(2 * cutoff)));
    }
  }
}

double mean_radius(const config::SizeDistribution& d) {
  switch (d.kind) {
    case config::SizeDistribution::Kind::Fixed:
      return d.value;
    case config::SizeDistribution::Kind::Uniform:
      return 0.5 * (d.min + d.max);
    default:
      return d.mean;
  }
}

/// Grains a lattice fill holds (spheres entirely inside the region), or the requested random count.
double estimate_fill(const config::Fill& f, const config::SizeDistribution& radius,
                     double& region_volume) {
  const double r = radius.largest();
  const double s = f.spacing.value_or(2 * r * 1.01);
  const bool hcp = f.lattice == config::Fill::Lattice::Hcp;
  double est = 0;
  if (f.region.kind == config::Region::Kind::Box) {
    const Vec3 len = f.region.max - f.region.min;
    region_volume = len.x * len.y * len.z;
    const double pitch[3] = {s, hcp ? s * std::sqrt(3.0) / 2 : s,
                             hcp ? s * std::sqrt(2.0 / 3.0) : s};
    est = 1;
    for (int k = 0; k < 3; ++k) {
      const double inner = len[k] - 2 * r;
      est *= inner < 0 ? 0 : std::floor(inner / pitch[k] + 1e-9) + 1;
    }
  } else {
    region_volume = std::numbers::pi * f.region.radius * f.region.radius * f.region.height;
    const double rr = f.region.radius - r, hh = f.region.height - 2 * r;
    est = (rr < 0 || hh < 0)
              ? 0
              : std::numbers::pi * rr * rr * hh / (s * s * s) * (hcp ? std::sqrt(2.0) : 1.0);
    est = std::floor(est);
  }
  if (f.lattice == config::Fill::Lattice::Random)
    est = f.count ? static_cast<double>(*f.count) : 0.0;
  if (f.count) est = std::min(est, static_cast<double>(*f.count));
  return est;
}

void Validator::estimate_counts() {
  double total = 0;
  for (std::size_t g = 0; g < c_.particles.size(); ++g) {
    const auto& group = c_.particles[g];
    if (group.fill) {
      const auto& f = *group.fill;
      double volume = 0;
      const double est = estimate_fill(f, group.radius, volume);
      const char* lattice = f.lattice == config::Fill::Lattice::Cubic ? "cubic"
                            : f.lattice == config::Fill::Lattice::Hcp ? "hcp"
                                                                      : "random";
      report_.derived.emplace_back(
          fmt::format("particles[{}]: grains (fill, {})", g, lattice),
          fmt::format("{}{:.0f}", f.lattice == config::Fill::Lattice::Random ? "" : "~", est));
      total += est;
      if (est < 1)
        report_.warnings.push_back(fmt::format(
            "particles[{}]: the fill region is too small to hold a grain of radius {} m", g,
            number_text(group.radius.largest())));
      if (f.lattice == config::Fill::Lattice::Random && volume > 0) {
        const double r = mean_radius(group.radius);
        const double fraction = est * 4.0 / 3.0 * std::numbers::pi * r * r * r / volume;
        report_.derived.emplace_back(
            fmt::format("particles[{}]: solid fraction asked of the random fill", g),
            fmt::format("{:.3f}", fraction));
        if (fraction > 0.35)
          report_.warnings.push_back(
              fmt::format("particles[{}]: a random fill rarely exceeds a solid fraction of about "
                          "0.35; {:.2f} is asked",
                          g, fraction));
      } else if (f.count && est < 0.8 * static_cast<double>(*f.count)) {
        // The estimate is a few per cent off for cylinders: warn only when clearly short.
        report_.warnings.push_back(
            fmt::format("particles[{}]: the lattice holds only ~{:.0f} grains, well below count {}",
                        g, est, *f.count));
      }
    } else if (group.explicit_particles) {
      const auto& ex = *group.explicit_particles;
      const double n = static_cast<double>(ex.positions.size());
      report_.derived.emplace_back(
          fmt::format("particles[{}]: grains (explicit{})", g,
                      ex.file.empty() ? "" : ", " + ex.file.filename().string()),
          fmt::format("{:.0f}", n));
      total += n;
    }
  }
  report_.derived.emplace_back("grains in total", fmt::format("~{:.0f}", total));
}

void Validator::check_time_step() {
  const double dt = c_.time.step;

  // Impact speed for the Hertz contact time.
  double v0 = 0;
  for (const auto& group : c_.particles) {
    if (group.fill)
      v0 = std::max(v0, norm(group.fill->velocity) + std::sqrt(3.0) * group.fill->velocity_jitter);
    if (group.explicit_particles)
      for (const auto& v : group.explicit_particles->velocities) v0 = std::max(v0, norm(v));
  }
  const Vec3 len = c_.domain.max - c_.domain.min;
  for (const auto& w : c_.walls) {
    double v = norm(w.motion.velocity);
    if (w.motion.rotates) {
      double reach = 0;
      if (w.kind == config::Wall::Kind::Cylinder) {
        reach = w.radius;
      } else {
        for (int corner = 0; corner < 8; ++corner) {
          const Vec3 p{corner & 1 ? c_.domain.max.x : c_.domain.min.x,
                       corner & 2 ? c_.domain.max.y : c_.domain.min.y,
                       corner & 4 ? c_.domain.max.z : c_.domain.min.z};
          const Vec3 d = p - w.motion.center;
          reach = std::max(reach, norm(d - dot(d, w.motion.axis) * w.motion.axis));
        }
      }
      v += std::abs(w.motion.rate) * reach;
    }
    v0 = std::max(v0, v);
  }
  const double g = norm(c_.gravity);
  double height = 0;
  if (g > 0)
    for (int k = 0; k < 3; ++k) height += std::abs(c_.gravity[k] / g) * len[k];
  const double v_impact = std::max(0.1, v0 + std::sqrt(2 * g * height));
  report_.derived.emplace_back(
      "impact speed used for the Hertz contact time (grain-grain: twice this, head-on)",
      fmt::format("{:.4g} m/s (initial {:.4g} m/s + free fall over {:.4g} m)", v_impact, v0,
                  height));

  auto to_material = [](const config::Material& m) {
    return Material{m.name, m.density, m.youngs_modulus, m.poisson_ratio};
  };
  auto mass = [&](const std::string& mat, double r) {
    return materials_.at(mat)->density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  };

  double tc_min = inf;
  std::string tc_what;
  std::set<std::string> elastic;  // materials whose contacts use the elastic moduli
  auto pair_time = [&](const std::string& a, const std::string& b, bool wall,
                       const std::string& label) {
    const config::Contact* ct = contacts_.at(std::minmax(a, b));
    const Material ma = to_material(*materials_.at(a)), mb = to_material(*materials_.at(b));
    const GrainSizes& ga = grains_.at(a);
    const double ra = ga.r_min;
    double r_eff = ra, m_eff = mass(a, ra), r_ref = ga.r_max;
    if (!wall) {
      const GrainSizes& gb = grains_.at(b);
      const double rb = gb.r_min, mb_ = mass(b, rb);
      r_eff = ra * rb / (ra + rb);
      m_eff = m_eff * mb_ / (m_eff + mb_);
      r_ref = std::max(r_ref, gb.r_max);
    }
    contact::PairContext ctx{&ma, &mb, r_ref};
    contact::PairCoeffs coeffs;
    try {
      coeffs = contact::prepare_pair(ct->model, ctx, ct->params);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw_input_error(at(ct->loc, "contacts"),
                        fmt::format("contact model '{}': {}", ct->model, e.what()));
    }
    // Two grains may meet head-on, each at the impact speed: twice that relative speed.
    const double tc = contact::contact_time(coeffs, r_eff, m_eff, wall ? v_impact : 2 * v_impact);
    report_.derived.emplace_back(fmt::format("contact time, {} ({})", label, ct->model),
                                 seconds(tc));
    if (tc < tc_min) {
      tc_min = tc;
      tc_what = fmt::format("contact time of {} ({})", label, ct->model);
    }
    if (ct->model != "hooke") {
      elastic.insert(a);
      if (!wall) elastic.insert(b);
    }
  };
  for (std::size_t i = 0; i < particle_materials_.size(); ++i)
    for (std::size_t j = 0; j <= i; ++j) {
      const auto& a = particle_materials_[j];
      const auto& b = particle_materials_[i];
      pair_time(a, b, false, fmt::format("{}-{} grains", a, b));
    }
  std::set<std::pair<std::string, std::string>> wall_pairs;
  for (const auto& w : c_.walls)
    for (const auto& pm : particle_materials_)
      if (wall_pairs.insert({pm, w.material}).second)
        pair_time(pm, w.material, true, fmt::format("{} grains on {} walls", pm, w.material));

  double tr_min = inf;
  std::string tr_what;
  for (const auto& m : particle_materials_) {
    const double r = grains_.at(m).r_min;
    const double tr = contact::rayleigh_time(to_material(*materials_.at(m)), r);
    report_.derived.emplace_back(fmt::format("Rayleigh time, {} (r = {} m)", m, number_text(r)),
                                 seconds(tr));
    if (elastic.count(m) && tr < tr_min) {
      tr_min = tr;
      tr_what = fmt::format("Rayleigh time of {} grains of radius {} m", m, number_text(r));
    }
  }
  if (tr_min < inf)
    report_.derived.emplace_back("time step / Rayleigh time", fmt::format("{:.3g}", dt / tr_min));
  if (tc_min < inf)
    report_.derived.emplace_back("time step / contact time", fmt::format("{:.3g}", dt / tc_min));
  const double t_lim = std::min(tr_min, tc_min);
  if (!(t_lim < inf)) return;
  const std::string& what = tr_min <= tc_min ? tr_what : tc_what;
  if (dt > 0.3 * t_lim) {
    throw_input_error(
        at(c_.time.loc, "time.step"),
        fmt::format(
            "expected a time step <= {:.3g} s (0.3 x the {}, {:.3g} s), found '{}' ({:.2f} x)",
            0.3 * t_lim, what, t_lim, number_text(dt), dt / t_lim));
  }
  if (dt > 0.15 * t_lim)
    report_.warnings.push_back(
        fmt::format("time step {} s is {:.2f} x the {} ({:.3g} s); 0.15 x or less is safer",
                    number_text(dt), dt / t_lim, what, t_lim));
}

void Validator::check_output() {
  const std::pair<const char*, double> blocks[] = {{"vtk", c_.output.vtk.every},
                                                   {"particles_csv", c_.output.particles_csv.every},
                                                   {"series", c_.output.series.every},
                                                   {"checkpoint", c_.output.checkpoint.every}};
  for (const auto& [name, every] : blocks)
    if (every > c_.time.end)
      report_.warnings.push_back(
          fmt::format("output.{}.every ({} s) is longer than the run (time.end = {} s): only "
                      "the initial state will be written",
                      name, number_text(every), number_text(c_.time.end)));
  double r_max = 0;
  for (const auto& [name, gs] : grains_) r_max = std::max(r_max, gs.r_max);
  report_.derived.emplace_back(
      "neighbor skin", c_.neighbor.skin ? fmt::format("{} m", number_text(*c_.neighbor.skin))
                                        : fmt::format("{} m (default: 0.25 x the largest diameter)",
                                                      number_text(0.5 * r_max)));
}

CheckReport Validator::run() {
  check_basics();
  check_materials();
  check_periodic();
  check_fills();
  check_explicit();
  check_overlaps(placed_);
  estimate_counts();
  check_time_step();
  check_output();
  return std::move(report_);
}

}  // namespace

CheckReport validate(const config::Case& c) {
  return Validator(c).run();
}

}  // namespace gf::input
