// SPDX-License-Identifier: GPL-3.0-or-later
// Echo of the resolved case as YAML through YAML::Emitter.
#include "io/input/echo.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>
#include <span>
#include <string>

#include "contact/registry.hpp"
#include "continuum/ktgf.hpp"
#include "continuum/rheology_registry.hpp"
#include "core/names.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "io/input/validate.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

namespace {

void emit_number(YAML::Emitter& out, double v) {
  out << number_text(v);
}

/// A vector of a case of dimension `dimension`: [x, y] in 2D, [x, y, z] in 3D.
void emit_vec(YAML::Emitter& out, const Vec3& v, int dimension) {
  out << YAML::Flow << YAML::BeginSeq;
  emit_number(out, v.x);
  emit_number(out, v.y);
  if (dimension != 2) emit_number(out, v.z);
  out << YAML::EndSeq;
}

void key_number(YAML::Emitter& out, const char* key, double v) {
  out << YAML::Key << key << YAML::Value;
  emit_number(out, v);
}

/// A model's parameters in schema order, each as given or at its default (none: left out).
void emit_schema_params(YAML::Emitter& out, std::span<const ParamSpec> schema,
                        const std::map<std::string, double>& given) {
  for (const auto& p : schema) {
    const auto g = given.find(std::string(p.name));
    const std::optional<double> v =
        g != given.end() ? std::optional<double>(g->second) : p.default_value;
    if (v) key_number(out, std::string(p.name).c_str(), *v);
  }
}

void key_vec(YAML::Emitter& out, const char* key, const Vec3& v, int dimension) {
  out << YAML::Key << key << YAML::Value;
  emit_vec(out, v, dimension);
}

void emit_vec_list(YAML::Emitter& out, const char* key, const std::vector<Vec3>& list,
                   int dimension) {
  out << YAML::Key << key << YAML::Value << YAML::BeginSeq;
  for (const auto& v : list) emit_vec(out, v, dimension);
  out << YAML::EndSeq;
}

/// The axis a spherocylinder's body axis e_z is turned to by q (3D).
Vec3 axis_of(const Quat& q) {
  Vec3 a = rotate(q, Vec3{0, 0, 1});
  for (int k = 0; k < 3; ++k)
    if (std::abs(a[k]) < 1e-15) a[k] = 0;  // rounding noise of the rotation
  return a;
}

/// The angle (rad, about z) of a rotation about z (2D).
double angle_of(const Quat& q) {
  return 2 * std::atan2(q.z, q.w);
}

void emit_orientation(YAML::Emitter& out, const Quat& q, int dimension) {
  out << YAML::Flow << YAML::BeginMap;
  if (dimension == 2) {
    key_number(out, "angle", angle_of(q));
  } else {
    out << YAML::Key << "axis" << YAML::Value;
    emit_vec(out, axis_of(q), 3);
  }
  out << YAML::EndMap;
}

void emit_size(YAML::Emitter& out, const config::ParticleGroup& g, bool radius_from_file);

void emit_radius(YAML::Emitter& out, const config::SizeDistribution& d) {
  using K = config::SizeDistribution::Kind;
  out << YAML::Key << "radius" << YAML::Value;
  if (d.kind == K::Fixed) {
    emit_number(out, d.value);
    return;
  }
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "distribution" << YAML::Value
      << (d.kind == K::Uniform  ? "uniform"
          : d.kind == K::Normal ? "normal"
                                : "lognormal");
  if (d.kind != K::Uniform) {
    key_number(out, "mean", d.mean);
    key_number(out, "std", d.std);
  }
  key_number(out, "min", d.min);
  key_number(out, "max", d.max);
  out << YAML::EndMap;
}

/// The keys of a region (fills, outlets): box {min, max} or cylinder {center, axis, radius,
/// height} (2D: {center, radius}).
void emit_region(YAML::Emitter& out, const config::Region& r, int dim) {
  if (r.kind == config::Region::Kind::Box) {
    out << YAML::Key << "box" << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_vec(out, "min", r.min, dim);
    key_vec(out, "max", r.max, dim);
    out << YAML::EndMap;
  } else {
    out << YAML::Key << "cylinder" << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_vec(out, "center", r.center, dim);
    if (dim == 3) key_vec(out, "axis", r.axis, dim);
    key_number(out, "radius", r.radius);
    if (dim == 3) key_number(out, "height", r.height);
    out << YAML::EndMap;
  }
}

void emit_fill(YAML::Emitter& out, const config::Fill& f, const config::ParticleGroup& g, int dim) {
  out << YAML::Key << "fill" << YAML::Value << YAML::BeginMap;
  emit_region(out, f.region, dim);
  const bool random = f.lattice == config::Fill::Lattice::Random;
  out << YAML::Key << "lattice" << YAML::Value
      << (f.lattice == config::Fill::Lattice::Cubic ? "cubic"
          : f.lattice == config::Fill::Lattice::Hcp ? "hcp"
                                                    : "random");
  if (!random) {
    if (f.spacing) {
      key_number(out, "spacing", *f.spacing);
    } else if (g.kind == config::Shape::Spherocylinder && f.orientation &&
               f.lattice == config::Fill::Lattice::Cubic) {
      out << YAML::Comment("spacing: default, 2.02 x the grain's half extent along each axis");
    } else {
      key_number(out, "spacing", 2 * bounding_radius(g, g.radius.largest()) * 1.01);
      out << YAML::Comment(g.kind == config::Shape::Sphere || g.kind == config::Shape::Disk
                               ? "default: 2.02 x the largest radius"
                               : "default: 2.02 x the largest bounding radius");
    }
  }
  if (f.volume_fraction) key_number(out, "volume_fraction", *f.volume_fraction);
  if (f.count) out << YAML::Key << "count" << YAML::Value << *f.count;
  out << YAML::Key << "seed" << YAML::Value << f.seed;
  key_vec(out, "velocity", f.velocity, dim);
  key_number(out, "velocity_jitter", f.velocity_jitter);
  if (random) {
    const std::int64_t attempts = f.max_attempts > 0 ? f.max_attempts : 1000 * f.count.value_or(0);
    out << YAML::Key << "max_attempts" << YAML::Value << attempts;
    if (f.max_attempts == 0) out << YAML::Comment("default: 1000 x count");
  }
  if (g.kind == config::Shape::Spherocylinder || g.kind == config::Shape::Polygon) {
    out << YAML::Key << "orientation" << YAML::Value;
    if (f.orientation)
      emit_orientation(out, *f.orientation, dim);
    else
      out << "random";
  }
  out << YAML::EndMap;
}

void emit_size(YAML::Emitter& out, const config::ParticleGroup& g, bool radius_from_file) {
  const bool vertices =
      g.kind == config::Shape::Polygon && g.polygon.kind == config::PolygonSpec::Kind::Vertices;
  if (!radius_from_file && !vertices) emit_radius(out, g.radius);
  if (g.kind == config::Shape::Spherocylinder) {
    if (g.length) {
      key_number(out, "length", *g.length);
      out << YAML::Comment("m, cylindrical part");
    } else if (g.aspect_ratio) {
      key_number(out, "aspect_ratio", *g.aspect_ratio);
      out << YAML::Comment("(L + 2 r)/(2 r)");
    }
  }
  if (g.kind != config::Shape::Polygon) return;
  const auto& p = g.polygon;
  out << YAML::Key << "polygon" << YAML::Value;
  switch (p.kind) {
    case config::PolygonSpec::Kind::Vertices:
      out << YAML::BeginMap << YAML::Key << "vertices" << YAML::Value << YAML::Flow
          << YAML::BeginSeq;
      for (const auto& v : p.vertices) emit_vec(out, v, 2);
      out << YAML::EndSeq << YAML::EndMap;
      out << YAML::Comment(fmt::format("equal-area radius {} m", number_text(g.radius.value)));
      break;
    case config::PolygonSpec::Kind::Regular:
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "regular" << YAML::Value << p.sides
          << YAML::EndMap;
      break;
    case config::PolygonSpec::Kind::Random:
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "random" << YAML::Value << YAML::BeginMap;
      out << YAML::Key << "vertices" << YAML::Value << YAML::BeginSeq << p.min_vertices
          << p.max_vertices << YAML::EndSeq;
      out << YAML::Key << "elongation" << YAML::Value << YAML::BeginSeq;
      emit_number(out, p.min_elongation);
      emit_number(out, p.max_elongation);
      out << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
      break;
  }
}

/// A prescribed motion, as walls[].motion and particles[].fixed take it: {translate, rotate}.
void emit_motion(YAML::Emitter& out, const config::Motion& m, int dim) {
  out << YAML::BeginMap;
  if (!(m.velocity == Vec3{})) {
    out << YAML::Key << "translate" << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_vec(out, "velocity", m.velocity, dim);
    key_number(out, "start", m.start);
    out << YAML::EndMap;
  }
  if (m.rotates) {
    out << YAML::Key << "rotate" << YAML::Value << YAML::Flow << YAML::BeginMap;
    if (dim != 2) key_vec(out, "axis", m.axis, dim);  // 2D: about z
    key_vec(out, "center", m.center, dim);
    key_number(out, "rate", m.rate);
    out << YAML::EndMap << YAML::Comment("rate in rad/s");
  }
  out << YAML::EndMap;
}

/// The CSV text (`particles[].file` columns) of a group's explicit particles.
std::string particles_csv(const config::ParticleGroup& g, int dim) {
  const auto& ex = *g.explicit_particles;
  const bool two_d = dim == 2;
  const bool v = !ex.velocities.empty(), w = !ex.angular_velocities.empty();
  const bool r = !ex.radii.empty(), q = !ex.orientations.empty();
  const bool rod = g.kind == config::Shape::Spherocylinder;
  fmt::memory_buffer text;
  auto out = std::back_inserter(text);
  fmt::format_to(out, "# {} particles of group '{}' ({}), written by grainflow\n",
                 ex.positions.size(), g.shape, g.material);
  fmt::format_to(out, "{}{}{}{}{}\n", two_d ? "x,y" : "x,y,z",
                 v ? (two_d ? ",vx,vy" : ",vx,vy,vz") : "", w ? (two_d ? ",wz" : ",wx,wy,wz") : "",
                 r ? ",radius" : "", q ? (rod ? ",qw,qx,qy,qz" : ",angle") : "");
  const auto number = [&](double x, bool first = false) {
    fmt::format_to(out, "{}{}", first ? "" : ",", number_text(x));
  };
  const auto vec = [&](const Vec3& a, bool first = false) {
    number(a.x, first);
    number(a.y);
    if (!two_d) number(a.z);
  };
  for (std::size_t i = 0; i < ex.positions.size(); ++i) {
    vec(ex.positions[i], true);
    if (v) vec(ex.velocities[i]);
    if (w) {
      if (two_d)
        number(ex.angular_velocities[i].z);
      else
        vec(ex.angular_velocities[i]);
    }
    if (r) number(ex.radii[i]);
    if (q) {
      const Quat& o = ex.orientations[i];
      if (rod) {
        for (const double c : {o.w, o.x, o.y, o.z}) number(c);
      } else {
        number(angle_of(o));
      }
    }
    fmt::format_to(out, "\n");
  }
  return fmt::to_string(text);
}

void emit_group(YAML::Emitter& out, const config::ParticleGroup& g, const config::Case& c,
                std::size_t index, std::vector<EchoFile>* files) {
  out << YAML::BeginMap;
  out << YAML::Key << "shape" << YAML::Value << g.shape;
  const bool radius_from_file = g.explicit_particles && !g.explicit_particles->radii.empty();
  emit_size(out, g, radius_from_file);
  out << YAML::Key << "material" << YAML::Value << g.material;
  if (g.temperature) key_number(out, "temperature", *g.temperature);
  if (g.heat_source) key_number(out, "heat_source", *g.heat_source);
  const int dim = c.dimension;
  out << YAML::Key << "fixed" << YAML::Value;
  if (g.motion)
    emit_motion(out, *g.motion, dim);  // a fixed group with a prescribed motion
  else
    out << g.fixed;
  if (g.fill) emit_fill(out, *g.fill, g, dim);
  if (g.inlet) {
    const auto& in = *g.inlet;
    out << YAML::Key << "inlet" << YAML::Value << YAML::BeginMap;
    emit_region(out, in.region, dim);
    if (in.mass_rate)
      key_number(out, "mass_rate", *in.mass_rate);
    else
      key_number(out, "rate", in.rate);
    key_vec(out, "velocity", in.velocity, dim);
    key_number(out, "start", in.start);
    if (in.stop) key_number(out, "stop", *in.stop);
    key_number(out, "every", in.every);
    out << YAML::EndMap;
  }
  if (g.explicit_particles) {
    const auto& ex = *g.explicit_particles;
    const std::size_t n = ex.positions.size();
    if (files && (!ex.file.empty() || n > echo_max_listed_particles)) {
      // A copy beside the resolved case: the run's folder then holds everything it ran from,
      // whatever becomes of the source file later.
      const std::string name = fmt::format("resolved_particles_{}.csv", index);
      files->push_back({name, particles_csv(g, dim)});
      out << YAML::Key << "file" << YAML::Value << name;
      out << YAML::Comment(fmt::format(
          "{} particles{}, from {}", n, radius_from_file ? " with their radii" : "",
          (ex.file.empty() ? c.file : std::filesystem::absolute(ex.file).lexically_normal())
              .string()));
    } else if (!ex.file.empty()) {
      out << YAML::Key << "file" << YAML::Value
          << std::filesystem::absolute(ex.file).lexically_normal().string();
      out << YAML::Comment(fmt::format(
          "{} particles{}", n, radius_from_file ? ", radii from the file's radius column" : ""));
    } else if (n > echo_max_listed_particles) {
      out << YAML::Key << "positions" << YAML::Value << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "count" << YAML::Value << n;
      out << YAML::Key << "source" << YAML::Value << c.file.string();
      out << YAML::EndMap << YAML::Comment("summarised: the list is in the source file");
    } else {
      emit_vec_list(out, "positions", ex.positions, dim);
      if (!ex.velocities.empty()) emit_vec_list(out, "velocities", ex.velocities, dim);
      if (!ex.angular_velocities.empty()) {
        if (dim == 2) {
          out << YAML::Key << "angular_velocities" << YAML::Value << YAML::Flow << YAML::BeginSeq;
          for (const auto& w : ex.angular_velocities) emit_number(out, w.z);
          out << YAML::EndSeq << YAML::Comment("rad/s about z");
        } else {
          emit_vec_list(out, "angular_velocities", ex.angular_velocities, dim);
        }
      }
      if (!ex.orientations.empty()) {
        if (g.kind == config::Shape::Spherocylinder) {
          out << YAML::Key << "axes" << YAML::Value << YAML::BeginSeq;
          for (const auto& q : ex.orientations) emit_vec(out, axis_of(q), 3);
          out << YAML::EndSeq;
        } else {
          out << YAML::Key << "angles" << YAML::Value << YAML::Flow << YAML::BeginSeq;
          for (const auto& q : ex.orientations) emit_number(out, angle_of(q));
          out << YAML::EndSeq << YAML::Comment("rad");
        }
      }
    }
  }
  out << YAML::EndMap;
}

void emit_wall(YAML::Emitter& out, const config::Wall& w, int dim) {
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << w.name;
  switch (w.kind) {
    case config::Wall::Kind::Plane:
      out << YAML::Key << "plane" << YAML::Value << YAML::Flow << YAML::BeginMap;
      key_vec(out, "point", w.point, dim);
      key_vec(out, "normal", w.normal, dim);
      out << YAML::EndMap;
      break;
    case config::Wall::Kind::Box: {
      out << YAML::Key << "box" << YAML::Value << YAML::Flow << YAML::BeginMap;
      key_vec(out, "min", w.min, dim);
      key_vec(out, "max", w.max, dim);
      std::vector<std::string> open;  // a 2D box has no z faces (recorded as open)
      for (const auto& face : w.open)
        if (dim != 2 || (face != "zmin" && face != "zmax")) open.push_back(face);
      out << YAML::Key << "open" << YAML::Value << YAML::Flow << open;
      out << YAML::EndMap;
      break;
    }
    case config::Wall::Kind::Mesh:
      out << YAML::Key << "mesh" << YAML::Value << YAML::Flow << YAML::BeginMap;
      // Absolute: the resolved case lives in the output folder, and a relative path is read
      // relative to the case file's folder.
      out << YAML::Key << "file" << YAML::Value
          << std::filesystem::absolute(w.mesh_file).lexically_normal().string();
      out << YAML::Key << "scale" << YAML::Value << w.mesh_scale;
      key_vec(out, "offset", w.mesh_offset, dim);
      out << YAML::EndMap;
      out << YAML::Comment(
          fmt::format("{} triangles, {} vertices{}", w.mesh_triangles.size(), w.mesh_points.size(),
                      w.mesh_dropped ? fmt::format(", {} degenerate left out", w.mesh_dropped)
                                     : std::string()));
      break;
    case config::Wall::Kind::Cylinder:
      out << YAML::Key << "cylinder" << YAML::Value << YAML::Flow << YAML::BeginMap;
      key_vec(out, "center", w.center, dim);
      if (dim == 3) key_vec(out, "axis", w.axis, dim);  // 2D: a circle, axis z
      key_number(out, "radius", w.radius);
      out << YAML::Key << "inside" << YAML::Value << w.inside;
      out << YAML::EndMap;
      break;
  }
  out << YAML::Key << "material" << YAML::Value << w.material;
  if (w.temperature) key_number(out, "temperature", *w.temperature);
  if (!(w.motion.velocity == Vec3{}) || w.motion.rotates) {
    out << YAML::Key << "motion" << YAML::Value;
    emit_motion(out, w.motion, dim);
  }
  if (w.servo) {
    out << YAML::Key << "servo" << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_number(out, "pressure", w.servo->pressure);
    key_number(out, "max_velocity", w.servo->max_velocity);
    out << YAML::Key << "span" << YAML::Value << YAML::BeginSeq;
    for (const auto& pr : w.servo->spans)
      out << YAML::Flow << YAML::BeginSeq << pr[0] << pr[1] << YAML::EndSeq;
    out << YAML::EndSeq;
    key_number(out, "gain", w.servo->gain);
    if (w.servo->until) key_number(out, "until", *w.servo->until);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

/// An interval as the case gave it: every_strain (strain) or every (s).
void key_interval(YAML::Emitter& out, double every, const std::optional<double>& every_strain) {
  if (every_strain)
    key_number(out, "every_strain", *every_strain);
  else
    key_number(out, "every", every);
}

void emit_every(YAML::Emitter& out, const char* key, const config::OutputEvery& e) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_interval(out, e.every, e.every_strain);
  out << YAML::EndMap;
  if (e.every == 0)
    out << YAML::Comment("off");
  else if (e.every_strain)
    out << YAML::Comment(fmt::format("every {} s", number_text(e.every)));
}

}  // namespace

std::string echo_yaml(const config::Case& c, std::string_view program_version,
                      std::vector<EchoFile>* files) {
  YAML::Emitter out;
  out.SetIndent(2);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << c.name;
  out << YAML::Key << "dimension" << YAML::Value << c.dimension;
  out << YAML::Key << "time" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_number(out, "step", c.time.step);
  const bool by_strain = c.shear && c.shear->strain;
  if (!by_strain) key_number(out, "end", c.time.end);
  out << YAML::EndMap
      << YAML::Comment(by_strain ? fmt::format("s; end = shear.strain / shear.rate = {} s",
                                               number_text(c.time.end))
                                 : std::string("s"));
  out << YAML::Key << "domain" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_vec(out, "min", c.domain.min, c.dimension);
  key_vec(out, "max", c.domain.max, c.dimension);
  out << YAML::Key << "periodic" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << c.domain.periodic[0] << c.domain.periodic[1];
  if (c.dimension != 2) out << c.domain.periodic[2];
  out << YAML::EndSeq;
  if (c.dimension == 2) key_number(out, "thickness", c.domain.thickness);
  out << YAML::EndMap << YAML::Comment("m");
  key_vec(out, "gravity", c.gravity, c.dimension);
  out << YAML::Comment("m/s^2");
  out << YAML::Key << "integrator" << YAML::Value << c.integrator;

  out << YAML::Key << "materials" << YAML::Value << YAML::BeginMap;
  for (const auto& m : c.materials) {
    out << YAML::Key << m.name << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_number(out, "density", m.density);
    key_number(out, "youngs_modulus", m.youngs_modulus);
    key_number(out, "poisson_ratio", m.poisson_ratio);
    if (m.thermal_conductivity) key_number(out, "thermal_conductivity", *m.thermal_conductivity);
    if (m.heat_capacity) key_number(out, "heat_capacity", *m.heat_capacity);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  if (c.heat) {
    out << YAML::Key << "heat" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "model" << YAML::Value << c.heat->model;
    key_number(out, "temperature", c.heat->temperature);
    out << YAML::EndMap << YAML::Comment("K");
  }

  out << YAML::Key << "contacts" << YAML::Value << YAML::BeginSeq;
  for (const auto& ct : c.contacts) {
    out << YAML::BeginMap;
    out << YAML::Key << "between" << YAML::Value << YAML::Flow << YAML::BeginSeq << ct.between[0]
        << ct.between[1] << YAML::EndSeq;
    out << YAML::Key << "model" << YAML::Value << ct.model;
    // Parameters in the order of the model's schema, then any others.
    std::vector<std::string> done;
    if (const auto* info = contact::find_model(ct.model)) {
      for (const auto& p : info->params) {
        auto it = ct.params.find(std::string(p.name));
        if (it == ct.params.end()) continue;
        key_number(out, it->first.c_str(), it->second);
        done.push_back(it->first);
      }
    }
    for (const auto& [k, v] : ct.params)
      if (std::find(done.begin(), done.end(), k) == done.end()) key_number(out, k.c_str(), v);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;

  out << YAML::Key << "particles" << YAML::Value << YAML::BeginSeq;
  for (std::size_t i = 0; i < c.particles.size(); ++i) emit_group(out, c.particles[i], c, i, files);
  out << YAML::EndSeq;

  // The shear walls are not echoed: the shear block makes them again.
  if (std::any_of(c.walls.begin(), c.walls.end(), [](const auto& w) { return !w.from_shear; })) {
    out << YAML::Key << "walls" << YAML::Value << YAML::BeginSeq;
    for (const auto& w : c.walls)
      if (!w.from_shear) emit_wall(out, w, c.dimension);
    out << YAML::EndSeq;
  }
  if (!c.outlets.empty()) {
    out << YAML::Key << "outlets" << YAML::Value << YAML::BeginSeq;
    for (const auto& o : c.outlets) {
      out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << o.name;
      emit_region(out, o.region, c.dimension);
      if (o.reinsert) {
        out << YAML::Key << "reinsert" << YAML::Value << YAML::Flow << YAML::BeginMap;
        emit_region(out, *o.reinsert, c.dimension);
        out << YAML::EndMap;
      }
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  if (!c.regions.empty()) {
    out << YAML::Key << "regions" << YAML::Value << YAML::BeginSeq;
    for (const auto& r : c.regions) {
      out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << r.name;
      emit_region(out, r.region, c.dimension);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  if (!c.flow_meters.empty()) {
    out << YAML::Key << "flow_meters" << YAML::Value << YAML::BeginSeq;
    for (const auto& f : c.flow_meters) {
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << f.name;
      key_vec(out, "point", f.point, c.dimension);
      key_vec(out, "normal", f.normal, c.dimension);
      if (f.radius) key_number(out, "radius", *f.radius);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  if (c.shear) {
    const auto& sh = *c.shear;
    const bool walls = sh.boundary == config::Shear::Boundary::Walls;
    out << YAML::Key << "shear" << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_number(out, "rate", sh.rate);
    out << YAML::Key << "boundary" << YAML::Value << (walls ? "walls" : "lees_edwards");
    if (walls) out << YAML::Key << "wall_material" << YAML::Value << sh.wall_material;
    if (sh.strain) key_number(out, "strain", *sh.strain);
    out << YAML::Key << "initial_profile" << YAML::Value << sh.initial_profile;
    out << YAML::EndMap << YAML::Comment("rate in 1/s");
  }
  if (c.analysis.rheology || c.analysis.mixing) {
    out << YAML::Key << "analysis" << YAML::Value << YAML::BeginMap;
    if (c.analysis.rheology) {
      const auto& r = *c.analysis.rheology;
      out << YAML::Key << "rheology" << YAML::Value << YAML::Flow << YAML::BeginMap;
      key_interval(out, r.every, r.every_strain);
      out << YAML::Key << "bins" << YAML::Value << r.bins;
      if (r.margin) key_number(out, "margin", *r.margin);
      if (r.start) key_number(out, "start", *r.start);
      out << YAML::EndMap;
      if (!r.margin) out << YAML::Comment("margin: one grain length next to walls");
    }
    if (c.analysis.mixing) {
      const auto& m = *c.analysis.mixing;
      out << YAML::Key << "mixing" << YAML::Value << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "materials" << YAML::Value << YAML::Flow << m.materials;
      key_number(out, "cell", m.cell);
      out << YAML::Key << "min_grains" << YAML::Value << m.min_grains;
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  if (c.sweep) {
    const auto& sw = *c.sweep;
    out << YAML::Key << "sweep" << YAML::Value << YAML::Flow << YAML::BeginMap;
    if (!sw.volume_fractions.empty())
      out << YAML::Key << "volume_fraction" << YAML::Value << YAML::Flow << sw.volume_fractions;
    if (!sw.shear_rates.empty())
      out << YAML::Key << "shear_rate" << YAML::Value << YAML::Flow << sw.shear_rates;
    if (sw.processes > 0) out << YAML::Key << "processes" << YAML::Value << sw.processes;
    out << YAML::EndMap;
  }

  if (c.fluid) {
    const auto& f = *c.fluid;
    out << YAML::Key << "fluid" << YAML::Value << YAML::BeginMap;
    key_number(out, "density", f.density);
    key_number(out, "viscosity", f.viscosity);
    out << YAML::Key << "cells" << YAML::Value << YAML::Flow << YAML::BeginSeq << f.cells[0]
        << f.cells[1] << f.cells[2] << YAML::EndSeq;
    out << YAML::Key << "boundary" << YAML::Value << YAML::BeginMap;
    const bool shear_walls = c.shear && c.shear->boundary == config::Shear::Boundary::Walls;
    for (int face = 0; face < 6; ++face) {
      if (shear_walls && face >= 4) continue;  // the shear walls (shear: block)
      const auto& b = f.boundary[static_cast<std::size_t>(face)];
      out << YAML::Key << std::string(kBoxFaceNames[static_cast<std::size_t>(face)]) << YAML::Value;
      using K = config::FluidBoundary::Kind;
      switch (b.kind) {
        case K::Periodic:
          out << "periodic";
          break;
        case K::NoSlip:
          if (!b.temperature) {
            out << "no_slip";
            break;
          }
          out << YAML::Flow << YAML::BeginMap << YAML::Key << "no_slip" << YAML::Value << true;
          key_number(out, "temperature", *b.temperature);
          out << YAML::EndMap;
          break;
        case K::MovingWall:
        case K::VelocityInlet:
          out << YAML::Flow << YAML::BeginMap;
          key_vec(out, b.kind == K::MovingWall ? "moving_wall" : "velocity_inlet", b.velocity,
                  c.dimension);
          if (b.temperature) key_number(out, "temperature", *b.temperature);
          out << YAML::EndMap;
          break;
        case K::PressureOutlet:
          out << YAML::Flow << YAML::BeginMap;
          key_number(out, "pressure_outlet", b.pressure);
          if (b.temperature) key_number(out, "temperature", *b.temperature);
          out << YAML::EndMap;
          break;
      }
      if (!b.given) out << YAML::Comment("default");
    }
    out << YAML::EndMap;
    key_vec(out, "initial_velocity", f.initial_velocity, c.dimension);
    out << YAML::Key << "convection" << YAML::Value << f.convection;
    if (c.coupling && !c.coupling->heat_transfer.empty()) {
      key_number(out, "heat_capacity", f.heat_capacity);
      key_number(out, "thermal_conductivity", f.thermal_conductivity);
      out << YAML::Key << "temperature_convection" << YAML::Value << f.temperature_convection;
      key_number(out, "temperature", f.temperature ? *f.temperature : c.heat->temperature);
      if (!f.temperature) out << YAML::Comment("heat.temperature");
      key_number(out, "thermal_expansion", f.thermal_expansion);
      if (f.thermal_expansion > 0)
        key_number(out, "reference_temperature",
                   f.reference_temperature.value_or(f.temperature.value_or(c.heat->temperature)));
    }
    out << YAML::EndMap;
  }
  if (c.coupling) {
    const auto& cp = *c.coupling;
    out << YAML::Key << "coupling" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "drag" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "model" << YAML::Value << cp.drag;
    if (const auto* law = cfd_dem::find_drag(cp.drag))
      emit_schema_params(out, law->params, cp.drag_params);
    out << YAML::EndMap;
    out << YAML::Key << "fluid_fraction" << YAML::Value << cp.fluid_fraction;
    out << YAML::Key << "interval" << YAML::Value << cp.interval;
    key_number(out, "min_fraction", cp.min_fraction);
    out << YAML::Key << "fluid_fraction_rate" << YAML::Value << cp.fluid_fraction_rate;
    key_number(out, "rate_relaxation", cp.rate_relaxation);
    out << YAML::Key << "pressure_gradient_force" << YAML::Value << cp.pressure_gradient_force;
    out << YAML::Key << "interpolation" << YAML::Value << cp.interpolation;
    out << YAML::Key << "torque" << YAML::Value << cp.torque;
    out << YAML::Key << "heat_transfer" << YAML::Value
        << (cp.heat_transfer.empty() ? std::string("none") : cp.heat_transfer);
    out << YAML::EndMap << YAML::Comment("fluid dt = interval x time.step");
  }

  out << YAML::Key << "output" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "directory" << YAML::Value << c.output.directory.string();
  emit_every(out, "vtk", c.output.vtk);
  emit_every(out, "particles_csv", c.output.particles_csv);
  emit_every(out, "contacts_csv", c.output.contacts_csv);
  emit_every(out, "contacts_vtk", c.output.contacts_vtk);
  out << YAML::Key << "series" << YAML::Value << YAML::BeginMap;
  key_interval(out, c.output.series.every, c.output.series.every_strain);
  out << YAML::Key << "quantities" << YAML::Value << YAML::Flow << c.output.quantities;
  out << YAML::EndMap;
  emit_every(out, "checkpoint", c.output.checkpoint);
  out << YAML::EndMap;

  if (c.neighbor.skin) {
    out << YAML::Key << "neighbor" << YAML::Value << YAML::Flow << YAML::BeginMap;
    key_number(out, "skin", *c.neighbor.skin);
    out << YAML::EndMap << YAML::Comment("m");
  }
  out << YAML::EndMap;

  std::string text =
      fmt::format("# grainflow {}: resolved configuration of {} (defaults filled in; SI units)\n",
                  program_version, c.file.string());
  if (!c.neighbor.skin)
    text += "# neighbor.skin: not set (default: 0.25 x the largest grain diameter)\n";
  text += out.c_str();
  text += "\n";
  return text;
}

namespace {

/// A continuum cylinder (a wall or a block) as its YAML map; a solid one (thickness 0) without
/// `thickness`, which is > 0 when given.
void emit_sph_cylinder(YAML::Emitter& out, const Vec3& center, const Vec3& axis, double radius,
                       double length, double thickness, int dim) {
  out << YAML::Key << "cylinder" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_vec(out, "center", center, dim);
  key_number(out, "radius", radius);
  if (thickness > 0) key_number(out, "thickness", thickness);
  if (dim == 3) {
    key_vec(out, "axis", axis, 3);
    key_number(out, "length", length);
  }
  out << YAML::EndMap;
}

void emit_sph_box(YAML::Emitter& out, const Vec3& lo, const Vec3& hi, int dim) {
  out << YAML::Key << "box" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_vec(out, "min", lo, dim);
  key_vec(out, "max", hi, dim);
  out << YAML::EndMap;
}

}  // namespace

std::string echo_continuum_yaml(const ContinuumCase& c, std::string_view program_version) {
  const auto& s = c.sph;
  const int dim = s.dimension;
  YAML::Emitter out;
  out.SetIndent(2);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << c.name;
  out << YAML::Key << "continuum" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "method" << YAML::Value << "sph";
  out << YAML::Key << "dimension" << YAML::Value << dim;
  out << YAML::Key << "domain" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_vec(out, "min", s.domain.lo, dim);
  key_vec(out, "max", s.domain.hi, dim);
  out << YAML::Key << "periodic" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int k = 0; k < dim; ++k) out << s.domain.periodic[static_cast<std::size_t>(k)];
  out << YAML::EndSeq << YAML::EndMap << YAML::Comment("m");
  key_vec(out, "gravity", s.gravity, dim);
  out << YAML::Comment("m/s^2");
  key_number(out, "spacing", s.spacing);
  out << YAML::Comment("m");
  key_number(out, "smoothing_ratio", s.smoothing_ratio);
  key_number(out, "density", s.density);
  out << YAML::Comment("kg/m^3");
  key_number(out, "sound_speed", s.sound_speed);
  out << YAML::Comment(c.sound_speed_given ? "m/s" : "m/s (default: 10 sqrt(2 |g| H))");
  key_number(out, "eos_exponent", s.eos_exponent);
  key_number(out, "background_pressure", s.background_pressure);
  out << YAML::Comment("Pa");
  key_number(out, "density_diffusion", s.density_diffusion);
  key_number(out, "artificial_viscosity", s.artificial_viscosity);

  out << YAML::Key << "rheology" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << c.rheology;
  if (const auto* info = continuum::find_rheology(c.rheology))
    emit_schema_params(out, info->params, c.rheology_params);
  out << YAML::EndMap;

  if (s.kinetic_theory) {
    out << YAML::Key << "kinetic_theory" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "closures" << YAML::Value << c.ktgf_closures;
    out << YAML::Key << "radial_distribution" << YAML::Value << c.ktgf_radial;
    if (const auto* set = continuum::find_ktgf_closure(c.ktgf_closures))
      emit_schema_params(out, set->params, c.ktgf_params);
    if (const auto* radial = continuum::find_radial_distribution(c.ktgf_radial))
      emit_schema_params(out, radial->params, c.ktgf_params);
    key_number(out, "initial_temperature", s.kinetic_theory->initial_temperature);
    key_number(out, "min_temperature", s.kinetic_theory->min_temperature);
    out << YAML::Comment("m^2/s^2");
    out << YAML::Key << "dense" << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "model" << YAML::Value << c.ktgf_dense;
    if (const auto* dense = continuum::find_frictional_model(c.ktgf_dense))
      emit_schema_params(out, dense->params, c.ktgf_dense_params);
    out << YAML::EndMap;
    out << YAML::EndMap;
  }

  out << YAML::Key << "time" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_number(out, "end", c.end_time);
  key_number(out, "cfl", s.cfl);
  key_number(out, "max_step", s.max_step);
  out << YAML::Key << "viscous" << YAML::Value << (s.implicit_viscosity ? "implicit" : "explicit");
  out << YAML::EndMap << YAML::Comment("s");

  out << YAML::Key << "blocks" << YAML::Value << YAML::BeginSeq;
  for (const auto& b : s.blocks) {
    out << YAML::Flow << YAML::BeginMap;
    if (b.shape == continuum::SphBlock::Shape::Box)
      emit_sph_box(out, b.lo, b.hi, dim);
    else
      emit_sph_cylinder(out, b.center, b.axis, b.radius, b.length, b.thickness, dim);
    key_vec(out, "velocity", b.velocity, dim);
    out << YAML::Key << "hydrostatic" << YAML::Value << b.hydrostatic;
    if (s.kinetic_theory && b.volume_fraction)
      key_number(out, "volume_fraction", *b.volume_fraction);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;

  if (!s.walls.empty()) {
    out << YAML::Key << "walls" << YAML::Value << YAML::BeginSeq;
    for (const auto& w : s.walls) {
      out << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "name" << YAML::Value << w.name;
      if (w.shape == continuum::SphWall::Shape::Box)
        emit_sph_box(out, w.lo, w.hi, dim);
      else
        emit_sph_cylinder(out, w.center, w.axis, w.radius, w.length, w.thickness, dim);
      key_vec(out, "velocity", w.velocity, dim);
      if (dim == 2)
        key_number(out, "angular_velocity", w.angular_velocity.z);
      else
        key_vec(out, "angular_velocity", w.angular_velocity, 3);
      if (w.rotation_center) key_vec(out, "rotation_center", *w.rotation_center, dim);
      key_number(out, "initial_angle", w.initial_angle);
      out << YAML::Key << "slip";
      if (w.johnson_jackson) {
        out << YAML::Value << YAML::Flow << YAML::BeginMap;
        key_number(out, "specularity", w.johnson_jackson->specularity);
        key_number(out, "wall_restitution", w.johnson_jackson->wall_restitution);
        out << YAML::EndMap;
      } else if (w.slip_length > 0.0 && !w.free_slip) {
        out << YAML::Value << YAML::Flow << YAML::BeginMap;
        key_number(out, "slip_length", w.slip_length);
        out << YAML::EndMap;
      } else {
        out << YAML::Value << (w.free_slip ? "free_slip" : "no_slip");
      }
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::Key << "output" << YAML::Value << YAML::Flow << YAML::BeginMap;
  key_number(out, "vtk_every", c.output.vtk_every);
  key_number(out, "series_every", c.output.series_every);
  key_number(out, "checkpoint_every", c.output.checkpoint_every);
  out << YAML::EndMap << YAML::Comment("s; 0: first and last / every step / final only");
  out << YAML::EndMap;
  out << YAML::EndMap;
  return fmt::format(
             "# grainflow {}: resolved configuration of {} (defaults filled in; SI units)\n",
             program_version, c.file) +
         out.c_str() + "\n";
}

}  // namespace gf::input
