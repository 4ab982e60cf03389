// SPDX-License-Identifier: GPL-3.0-or-later
// Dispatch of `fluid_fem:` cases from the grainflow command line, and their HDF5 checkpoints.
#include "simulation/fem_case.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <limits>
#include <memory>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"
#include "core/version.hpp"
#include "coupling/fem_dem/moving_bodies.hpp"
#include "io/input/yaml_reader.hpp"
#include "io/restart/h5.hpp"

namespace gf {

namespace fs = std::filesystem;

std::optional<fem::FemCaseConfig> load_fem_case(const fs::path& file, fs::path& output_dir,
                                                const std::vector<input::Override>& overrides) {
  // The shared reader: YAML syntax errors, and --set values located as in every other case
  // ("case.yaml (--set KEY=VALUE): error: ..."), which positions in the file cannot tell.
  const auto root = input::YamlNode::parse_file(file);
  if (!root.is_map() || !root.raw()["fluid_fem"]) return std::nullopt;
  input::apply_overrides(root.raw(), overrides, file);
  const input::YamlMap top(root, {"name", "fluid_fem", "output"});
  output_dir = fs::path("out") / file.parent_path().filename();
  if (const auto out = top.find("output")) {
    if (!out->is_map() || out->raw().size() != 1 || !out->raw()["directory"] ||
        !out->raw()["directory"].IsScalar())
      out->fail_expected(
          "{directory: FOLDER} in a fluid_fem case (the FEM outputs are configured in "
          "fluid_fem.output)");
    output_dir = input::YamlMap(*out, {"directory"}).string("directory");
  }
  const auto name = std::make_shared<const std::string>(file.string());
  const fem::ErrorText text = [name](const YAML::Node& at, const YAML::Mark& key_mark,
                                     const std::string& path, const std::string& message) {
    const input::YamlNode node(at, path, name, key_mark);
    return input::format_error(key_mark.is_null() ? node.loc() : node.key_loc(), message);
  };
  auto cfg = fem::parse_fluid_fem(top.at("fluid_fem").raw(), file.string(), text);
  cfg.name = top.has("name") ? top.string("name") : file.parent_path().filename().string();
  cfg.output_directory = output_dir.string();
  return cfg;
}

namespace {

// The moving mesh of a run with free bodies (fem::MovingFlowState and the moving part of
// NavierStokes::State): point lists as flat x, y arrays, the mesh's topology as int32 arrays.
std::vector<double> flat(const std::vector<fem::Vec2>& p) {
  std::vector<double> v;
  v.reserve(2 * p.size());
  for (const auto& q : p) v.insert(v.end(), {q.x, q.y});
  return v;
}

std::vector<fem::Vec2> points(const std::vector<double>& v) {
  std::vector<fem::Vec2> p;
  p.reserve(v.size() / 2);
  for (std::size_t i = 0; i + 1 < v.size(); i += 2) p.push_back({v[i], v[i + 1]});
  return p;
}

void save_points(io::h5::File& h, const std::string& name, const std::vector<fem::Vec2>& p) {
  const auto v = flat(p);
  h.write(name, std::span<const double>(v));
}

void save_moving(io::h5::File& h, const fem::NavierStokes::State& f,
                 const fem::MovingFlowState& m) {
  h.set_attribute("/", "moving", std::int64_t{1});
  h.create_group("moving");
  auto dbl = [&h](const std::string& name, const std::vector<double>& v) {
    h.write("moving/" + name, std::span<const double>(v));
  };
  auto pts = [&h](const std::string& name, const std::vector<fem::Vec2>& p) {
    save_points(h, "moving/" + name, p);
  };
  // the flow's moving mesh
  h.set_attribute("moving", "flow_moving", static_cast<std::int64_t>(f.moving));
  pts("nodes", f.nodes);
  pts("centres", f.centres);
  h.set_attribute("moving", "hist_nodes", static_cast<std::int64_t>(f.hist_nodes.size()));
  for (std::size_t k = 0; k < f.hist_nodes.size(); ++k) {
    pts(fmt::format("hist_nodes_{}", k), f.hist_nodes[k]);
    pts(fmt::format("hist_centres_{}", k), f.hist_centres[k]);
  }
  pts("mesh_w", f.mesh_w);
  pts("factor_nodes", f.factor_nodes);
  pts("factor_centres", f.factor_centres);
  pts("factor_w", f.factor_w);
  std::vector<double> loads;
  for (const auto& l : f.body_load) loads.insert(loads.end(), {l.force.x, l.force.y, l.torque});
  dbl("body_load", loads);
  // the bodies as meshed: kind (0 circle, 1 polygon), centre, radius, vertices
  std::vector<std::int32_t> kind, n_vertices;
  std::vector<double> body;
  std::vector<fem::Vec2> vertices;
  for (const auto& b : m.reference_bodies) {
    kind.push_back(b.kind == fem::BodyShape::Kind::Circle ? 0 : 1);
    n_vertices.push_back(static_cast<std::int32_t>(b.vertices.size()));
    body.insert(body.end(), {b.centre.x, b.centre.y, b.radius});
    vertices.insert(vertices.end(), b.vertices.begin(), b.vertices.end());
  }
  h.write("moving/body_kind", std::span<const std::int32_t>(kind));
  h.write("moving/body_n_vertices", std::span<const std::int32_t>(n_vertices));
  dbl("body_centre_radius", body);
  pts("body_vertices", vertices);
  dbl("body_density", m.body_density);
  // the mesh as built
  const auto& mesh = m.reference_mesh;
  pts("mesh_nodes", mesh.nodes);
  h.set_attribute("moving", "mesh_vertices", static_cast<std::int64_t>(mesh.n_vertices));
  std::vector<std::int32_t> cells, boundary;
  for (const auto& c : mesh.cells) cells.insert(cells.end(), c.begin(), c.end());
  for (const auto& e : mesh.boundary)
    boundary.insert(boundary.end(),
                    {e.a, e.b, e.mid, e.cell, e.local_edge, e.outline_edge, e.body});
  h.write("moving/mesh_cells", std::span<const std::int32_t>(cells));
  h.write("moving/mesh_curved", std::span<const std::uint8_t>(mesh.curved));
  h.write("moving/mesh_boundary", std::span<const std::int32_t>(boundary));
  // the bodies' motion and contacts
  dbl("reference_poses", m.reference_poses);
  dbl("poses", m.poses);
  dbl("previous_velocity", m.previous_velocity);
  h.set_attribute("moving", "previous_dt", m.previous_dt);
  dbl("external_loads", m.external_loads);
  dbl("contact_loads", m.contact_loads);
  std::vector<std::int64_t> keys(m.history_keys.begin(), m.history_keys.end());
  h.write("moving/history_keys", std::span<const std::int64_t>(keys));
  dbl("history_stretch", m.history_stretch);
  dbl("history_roll", m.history_roll);
  dbl("history_roll", m.history_roll);
  h.set_attribute("moving", "remeshes", m.remeshes);
  h.set_attribute("moving", "remesh_seconds", m.remesh_seconds);
}

fem::MovingFlowState load_moving(const io::h5::File& h, fem::NavierStokes::State& f) {
  // (what is read is checked before it reaches the solver: a damaged or foreign file is an
  // IoError, which --restart reports as bad input)
  auto bad = [&h](const std::string& what) {
    return IoError(
        fmt::format("{}: not a valid moving-mesh checkpoint: {}", h.path().string(), what));
  };
  auto dbl = [&h](const std::string& name) { return h.read_double("moving/" + name); };
  auto pts = [&](const std::string& name) {
    const auto v = dbl(name);
    if (v.size() % 2 != 0)
      throw bad(fmt::format("'{}' holds {} numbers, not x, y pairs", name, v.size()));
    return points(v);
  };
  f.moving = h.read_int_attribute("moving", "flow_moving") != 0;
  f.nodes = pts("nodes");
  f.centres = pts("centres");
  const auto n_hist = h.read_int_attribute("moving", "hist_nodes");
  if (n_hist < 0 || n_hist > fem::kMaxBdfOrder + 1)
    throw bad(fmt::format("{} history node lists", n_hist));
  for (std::int64_t k = 0; k < n_hist; ++k) {
    f.hist_nodes.push_back(pts(fmt::format("hist_nodes_{}", k)));
    f.hist_centres.push_back(pts(fmt::format("hist_centres_{}", k)));
  }
  f.mesh_w = pts("mesh_w");
  f.factor_nodes = pts("factor_nodes");
  f.factor_centres = pts("factor_centres");
  f.factor_w = pts("factor_w");
  const auto loads = dbl("body_load");
  if (loads.size() % 3 != 0) throw bad("body loads are not (fx, fy, torque) triples");
  for (std::size_t i = 0; i + 2 < loads.size(); i += 3)
    f.body_load.push_back({{loads[i], loads[i + 1]}, loads[i + 2]});
  fem::MovingFlowState m;
  const auto kind = h.read_int32("moving/body_kind");
  const auto n_vertices = h.read_int32("moving/body_n_vertices");
  const auto body = dbl("body_centre_radius");
  const auto vertices = pts("body_vertices");
  if (!h.exists("moving/body_density"))
    throw bad(
        "no body densities (written by a build of 2026-12-04 before they were kept: run "
        "the case again from the start)");
  m.body_density = dbl("body_density");
  const std::size_t nb = kind.size();
  if (n_vertices.size() != nb || body.size() != 3 * nb || m.body_density.size() != nb)
    throw bad(fmt::format("{} bodies, but {} vertex counts, {} centre/radius numbers, {} densities",
                          nb, n_vertices.size(), body.size(), m.body_density.size()));
  std::size_t next = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    if (kind[b] != 0 && kind[b] != 1) throw bad(fmt::format("body {} of kind {}", b, kind[b]));
    if (n_vertices[b] < 0 || static_cast<std::size_t>(n_vertices[b]) > vertices.size() - next)
      throw bad(
          fmt::format("body {}: {} vertices, {} left", b, n_vertices[b], vertices.size() - next));
    fem::BodyShape s;
    s.kind = kind[b] == 0 ? fem::BodyShape::Kind::Circle : fem::BodyShape::Kind::Polygon;
    s.centre = {body[3 * b], body[3 * b + 1]};
    s.radius = body[3 * b + 2];
    const auto nv = static_cast<std::size_t>(n_vertices[b]);
    s.vertices.assign(vertices.begin() + static_cast<std::ptrdiff_t>(next),
                      vertices.begin() + static_cast<std::ptrdiff_t>(next + nv));
    next += nv;
    m.reference_bodies.push_back(std::move(s));
  }
  if (next != vertices.size())
    throw bad(fmt::format("{} body vertices, {} used", vertices.size(), next));
  auto& mesh = m.reference_mesh;
  mesh.nodes = pts("mesh_nodes");
  mesh.n_vertices = static_cast<int>(h.read_int_attribute("moving", "mesh_vertices"));
  const auto n_nodes = static_cast<std::int64_t>(mesh.nodes.size());
  const auto cells = h.read_int32("moving/mesh_cells");
  mesh.curved = h.read_uint8("moving/mesh_curved");
  const auto boundary = h.read_int32("moving/mesh_boundary");
  if (mesh.n_vertices < 3 || mesh.n_vertices > n_nodes || cells.size() % 6 != 0 ||
      boundary.size() % 7 != 0 || mesh.curved.size() != cells.size() / 6)
    throw bad(
        fmt::format("a mesh of {} nodes, {} vertices, {} cell indices, {} curved flags, {} "
                    "boundary numbers",
                    n_nodes, mesh.n_vertices, cells.size(), mesh.curved.size(), boundary.size()));
  const auto n_cells = static_cast<std::int64_t>(cells.size() / 6);
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (cells[i] < 0 || cells[i] >= (i % 6 < 3 ? mesh.n_vertices : n_nodes))
      throw bad(fmt::format("cell {} refers to node {}", i / 6, cells[i]));
  for (std::size_t i = 0; i < cells.size(); i += 6)
    mesh.cells.push_back(
        {cells[i], cells[i + 1], cells[i + 2], cells[i + 3], cells[i + 4], cells[i + 5]});
  for (std::size_t i = 0; i < boundary.size(); i += 7) {
    const fem::BoundaryEdge e{boundary[i],     boundary[i + 1], boundary[i + 2], boundary[i + 3],
                              boundary[i + 4], boundary[i + 5], boundary[i + 6]};
    const bool ok = e.a >= 0 && e.a < mesh.n_vertices && e.b >= 0 && e.b < mesh.n_vertices &&
                    e.mid >= 0 && e.mid < n_nodes && e.cell >= 0 && e.cell < n_cells &&
                    e.local_edge >= 0 && e.local_edge < 3 && e.outline_edge >= -1 && e.body >= -1 &&
                    e.body < static_cast<int>(nb) && (e.outline_edge >= 0) != (e.body >= 0);
    if (!ok) throw bad(fmt::format("boundary edge {}", i / 7));
    mesh.boundary.push_back(e);
  }
  m.reference_poses = dbl("reference_poses");
  m.poses = dbl("poses");
  m.previous_velocity = dbl("previous_velocity");
  m.previous_dt = h.read_double_attribute("moving", "previous_dt");
  m.external_loads = dbl("external_loads");
  m.contact_loads = dbl("contact_loads");
  for (const auto k : h.read_int64("moving/history_keys"))
    m.history_keys.push_back(static_cast<std::uint64_t>(k));
  m.history_stretch = dbl("history_stretch");
  // (no rolling springs before 2026-12-04: none turned)
  m.history_roll = h.exists("moving/history_roll")
                       ? dbl("history_roll")
                       : std::vector<double>(m.history_stretch.size(), 0.0);
  // the flow's moving mesh: node lists of this mesh, one per known state
  auto fits = [&](const std::vector<fem::Vec2>& nodes, const std::vector<fem::Vec2>& centres) {
    return static_cast<std::int64_t>(nodes.size()) == n_nodes && centres.size() == nb;
  };
  bool flow_ok = !f.moving || (fits(f.nodes, f.centres) && f.hist_nodes.size() == f.hist_t.size() &&
                               static_cast<std::int64_t>(f.mesh_w.size()) == n_nodes);
  for (std::size_t k = 0; flow_ok && k < f.hist_nodes.size(); ++k)
    flow_ok = fits(f.hist_nodes[k], f.hist_centres[k]);
  if (flow_ok && f.moving && f.factorized)
    flow_ok = fits(f.factor_nodes, f.factor_centres) &&
              (f.factor_w.empty() || static_cast<std::int64_t>(f.factor_w.size()) == n_nodes);
  if (!flow_ok) throw bad("node lists that do not fit the mesh");
  auto per_body = [nb](const std::vector<double>& v, bool may_be_empty) {
    return v.size() == 3 * nb || (may_be_empty && v.empty());
  };
  if (!per_body(m.reference_poses, false) || !per_body(m.poses, false) ||
      !per_body(m.previous_velocity, true) || !per_body(m.external_loads, true) ||
      !per_body(m.contact_loads, false))
    throw bad(fmt::format("poses, velocities or loads not of {} bodies", nb));
  if (m.history_keys.size() != m.history_stretch.size() ||
      m.history_keys.size() != m.history_roll.size())
    throw bad(fmt::format("{} friction-spring keys, {} stretches, {} rotations",
                          m.history_keys.size(), m.history_stretch.size(), m.history_roll.size()));
  m.remeshes = h.read_int_attribute("moving", "remeshes");
  m.remesh_seconds = h.read_double_attribute("moving", "remesh_seconds");
  return m;
}

}  // namespace

void save_fem_checkpoint(const fs::path& file, const fem::FemCheckpoint& c) {
  io::write_checkpoint_atomically(file, [&](io::h5::File& h) {
    const auto& f = c.flow;
    io::set_checkpoint_identity(h, "fluid_fem");
    h.set_attribute("/", "time", f.t);
    h.set_attribute("/", "steps", c.steps);
    h.set_attribute("/", "n_fields", c.n_fields);
    h.set_attribute("/", "next_vtk", c.next_vtk);
    h.set_attribute("/", "next_csv", c.next_csv);
    h.set_attribute("/", "next_checkpoint", c.next_checkpoint);
    h.set_attribute("/", "mesh_hash", static_cast<std::int64_t>(c.mesh_hash));
    if (c.fields_until) h.set_attribute("/", "fields_until", *c.fields_until);
    h.set_attribute("/", "runs", c.runs);
    h.set_attribute("/", "wall_seconds", c.wall_seconds);
    h.create_group("loop");
    h.set_attribute("loop", "dt", c.loop.dt);
    h.set_attribute("loop", "dt_config", c.loop.dt_config);
    h.set_attribute("loop", "order", static_cast<std::int64_t>(c.loop.order));
    h.set_attribute("loop", "same_order_steps", static_cast<std::int64_t>(c.loop.same_order_steps));
    h.set_attribute("loop", "error_rejections", static_cast<std::int64_t>(c.loop.error_rejections));
    h.create_group("flow");
    h.set_attribute("flow", "last_order", static_cast<std::int64_t>(f.last_order));
    h.set_attribute("flow", "alpha0", f.alpha0);
    h.write("flow/x", std::span<const double>(f.x));
    h.write("flow/hist_t", std::span<const double>(f.hist_t));
    for (std::size_t k = 0; k < f.hist_x.size(); ++k)
      h.write(fmt::format("flow/hist_x_{}", k), std::span<const double>(f.hist_x[k]));
    h.write("flow/hist_term", std::span<const double>(f.hist_term));
    h.set_attribute("flow", "factorized", static_cast<std::int64_t>(f.factorized));
    if (f.factorized) {
      h.write("flow/factor_x", std::span<const double>(f.factor_x));
      h.set_attribute("flow", "factor_alpha0", f.factor_alpha0);
      h.set_attribute("flow", "factor_newton", static_cast<std::int64_t>(f.factor_newton));
    }
    if (c.moving) save_moving(h, f, *c.moving);
  });
}

fem::FemCheckpoint load_fem_checkpoint(const fs::path& file) {
  auto h = io::h5::File::open_read(file);
  if (io::checkpoint_kind(h, file) != "fluid_fem")
    throw InputError(fmt::format(
        "{}: a particle (DEM / CFD-DEM) checkpoint; a fluid_fem case continues only from a "
        "fem_checkpoint_*.h5 of a fluid_fem run",
        file.string()));
  fem::FemCheckpoint c;
  auto& f = c.flow;
  f.t = h.read_double_attribute("/", "time");
  c.steps = h.read_int_attribute("/", "steps");
  c.n_fields = h.read_int_attribute("/", "n_fields");
  c.next_vtk = h.read_double_attribute("/", "next_vtk");
  c.next_csv = h.read_double_attribute("/", "next_csv");
  c.next_checkpoint = h.read_double_attribute("/", "next_checkpoint");
  c.mesh_hash = static_cast<std::uint64_t>(h.read_int_attribute("/", "mesh_hash"));
  // (not in checkpoints before 2026-12-01: then no schedule time, one run, wall time unknown)
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (h.has_attribute("/", "fields_until"))
    c.fields_until = h.read_double_attribute("/", "fields_until");
  c.runs = h.has_attribute("/", "runs") ? h.read_int_attribute("/", "runs") : 1;
  c.wall_seconds =
      h.has_attribute("/", "wall_seconds") ? h.read_double_attribute("/", "wall_seconds") : nan;
  c.loop.dt = h.read_double_attribute("loop", "dt");
  c.loop.dt_config = h.read_double_attribute("loop", "dt_config");
  c.loop.order = static_cast<int>(h.read_int_attribute("loop", "order"));
  c.loop.same_order_steps = static_cast<int>(h.read_int_attribute("loop", "same_order_steps"));
  c.loop.error_rejections = static_cast<int>(h.read_int_attribute("loop", "error_rejections"));
  f.last_order = static_cast<int>(h.read_int_attribute("flow", "last_order"));
  f.alpha0 = h.read_double_attribute("flow", "alpha0");
  f.x = h.read_double("flow/x");
  f.hist_t = h.read_double("flow/hist_t");
  for (std::size_t k = 0; k < f.hist_t.size(); ++k)
    f.hist_x.push_back(h.read_double(fmt::format("flow/hist_x_{}", k)));
  f.hist_term = h.read_double("flow/hist_term");
  f.factorized = h.read_int_attribute("flow", "factorized") != 0;
  if (f.factorized) {
    f.factor_x = h.read_double("flow/factor_x");
    f.factor_alpha0 = h.read_double_attribute("flow", "factor_alpha0");
    f.factor_newton = h.read_int_attribute("flow", "factor_newton") != 0;
  }
  if (h.has_attribute("/", "moving")) c.moving = load_moving(h, f);
  return c;
}

namespace {

/// The moving-mesh options of a case (its moving_mesh keys default to MovingBodyOptions' values:
/// FemMovingCase.ParsesFreeBodies checks it).
fem_dem::MovingBodyOptions moving_options(const fem::FemCaseConfig& cfg) {
  fem_dem::MovingBodyOptions o;
  o.remesh_ratio = cfg.remesh_ratio;
  o.remesh_quality = cfg.remesh_quality;
  o.collision = {cfg.repulsion_range, cfg.repulsion_force, cfg.repulsion_friction,
                 cfg.repulsion_tangential_stiffness, cfg.repulsion_rolling_friction,
                 cfg.repulsion_core};
  o.body_names = cfg.body_names;
  return o;
}

/// A case's free bodies moving through the flow: fem_dem::MovingBodyFlow behind the interface
/// run_fluid_fem knows.
class MovingFlow final : public fem::FemMovingFlow {
 public:
  MovingFlow(fem::FlowProblem pb, const fem::FemCaseConfig& cfg)
      : run_(std::move(pb), moving_options(cfg)) {}
  [[nodiscard]] const fem::NavierStokes& flow() const override { return run_.flow(); }
  fem::StepResult try_step(double dt, int order, const fem::NewtonOptions& newton, double rtol,
                           double atol, bool neighbour_errors) override {
    return run_.try_step(dt, order, newton, rtol, atol, neighbour_errors);
  }
  void accept_step() override { run_.accept_step(); }
  void reject_step() override { run_.reject_step(); }
  [[nodiscard]] fem::Vec2 centre(int body) const override { return run_.poses()[body].centre; }
  [[nodiscard]] double angle(int body) const override { return run_.poses()[body].angle; }
  [[nodiscard]] int remeshes() const override { return run_.remeshes(); }
  [[nodiscard]] fem::MovingFlowState state() const override { return run_.state(); }
  void restore(const fem::NavierStokes::State& flow, const fem::MovingFlowState& s) override {
    run_.restore(flow, s);
  }

 private:
  fem_dem::MovingBodyFlow run_;
};

}  // namespace

int run_fem_case(const fem::FemCaseConfig& cfg, const fs::path& default_dir,
                 const RunOptions& opts) {
  const fs::path dir = opts.output.empty() ? default_dir : opts.output;
  // Read before the output folder is prepared: --overwrite may empty the folder it lies in.
  check_append(dir, opts);
  std::optional<fem::FemCheckpoint> resume;
  if (opts.restart) resume = load_restart(*opts.restart, load_fem_checkpoint);
  OutputFolder folder(dir, opts);
  log::info("fluid_fem run, output in '{}'", dir.string());
  for (const auto& w : cfg.warnings) log::warn("{}", w);
  write_atomically(dir / "resolved_case.yaml",
                   [&](std::ostream& o) { o << fem::echo_fluid_fem_yaml(cfg, version_string); });
  fem::FemCheckpointIo io;
  io.save = save_fem_checkpoint;
  io.append = opts.append;
  if (resume) {
    io.resume = &*resume;
    log::info("continuing from '{}' at t = {} s (step {})", opts.restart->string(), resume->flow.t,
              resume->steps);
  }
  const int sig = fem::run_fluid_fem(cfg, dir, opts.steps ? static_cast<int>(*opts.steps) : -1, io,
                                     [](fem::FlowProblem pb, const fem::FemCaseConfig& c) {
                                       return std::make_unique<MovingFlow>(std::move(pb), c);
                                     });
  if (sig)
    log::warn("fluid_fem run stopped by {}: outputs up to the last step written in '{}'",
              stop::signal_name(sig), dir.string());
  folder.commit();
  return sig;
}

}  // namespace gf
