// SPDX-License-Identifier: GPL-3.0-or-later
// The typed case configuration: what a validated case.yaml becomes (SI units throughout).
//
// The YAML reader (parse_case.cpp) fills these structs, fills in defaults, and checks types and
// ranges with file:line:column locations; validate.cpp does the cross-checks that need several
// blocks at once. Nothing downstream reads YAML.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/quaternion.hpp"
#include "core/vec3.hpp"

namespace gf::config {

/// Where a value came from, for error messages raised after parsing.
struct SourceLoc {
  std::string file;
  int line = 0;          ///< 1-based; 0 = unknown
  int column = 0;        ///< 1-based
  std::string key_path;  ///< e.g. "particles[0].fill.count"
};

struct Time {
  double step = 0;  ///< s
  double end = 0;   ///< s
  SourceLoc loc;
};

/// In 2D (dimension: 2) the vectors have z = 0 (the YAML gives two components) and periodic[2]
/// is false; `thickness` is the depth of the grains (m), used for masses: a disk or polygon of
/// area A has mass density * A * thickness.
struct DomainBox {
  Vec3 min, max;  ///< m
  std::array<bool, 3> periodic{false, false, false};
  double thickness = 1.0;  ///< 2D only, m
  SourceLoc loc;
};

struct Material {
  std::string name;
  double density = 0;         ///< kg/m^3
  double youngs_modulus = 0;  ///< Pa
  double poisson_ratio = 0;   ///< 1
  /// Thermal properties (heat: block): conductivity W/(m K), specific heat capacity J/(kg K).
  std::optional<double> thermal_conductivity, heat_capacity;
  SourceLoc loc;
};

/// One entry of `contacts:`; `params` holds the model's parameters by schema name, defaults
/// filled in (validated against the model's schema from the contact registry).
struct Contact {
  std::array<std::string, 2> between;
  std::string model;  ///< registry key: hooke | hertz_mindlin
  std::map<std::string, double> params;
  SourceLoc loc;
  std::map<std::string, SourceLoc> param_locs;     ///< where each parameter given was written
  std::map<std::string, std::string> param_found;  ///< each given parameter as written ('1.0e4')
};

/// Radius: a fixed value or a distribution with cut-offs (all in m).
struct SizeDistribution {
  enum class Kind { Fixed, Uniform, Normal, Lognormal };
  Kind kind = Kind::Fixed;
  double value = 0;  ///< Fixed
  double min = 0;    ///< cut-off (Uniform: bounds; Normal / Lognormal: truncation)
  double max = 0;
  double mean = 0;  ///< Normal / Lognormal: mean of the radius
  double std = 0;   ///< Normal / Lognormal: standard deviation of the radius
  double largest() const { return kind == Kind::Fixed ? value : max; }
  double smallest() const { return kind == Kind::Fixed ? value : min; }
};

struct Region {
  enum class Kind { Box, Cylinder };
  Kind kind = Kind::Box;
  Vec3 min, max;       ///< Box
  Vec3 center;         ///< Cylinder: a point on the axis (bottom end)
  Vec3 axis{0, 0, 1};  ///< Cylinder: unit axis
  double radius = 0;   ///< Cylinder
  double height = 0;   ///< Cylinder: extent from `center` along `axis`
};

/// An outlet: grains whose centre is inside `region` leave the simulation (removed at the next
/// neighbour-list rebuild; fixed grains never), their number and mass counted per outlet. With
/// `reinsert` they are put back instead, at rest, at a random free place of that region (a
/// silo or hopper recirculated to a steady flow).
struct Outlet {
  std::string name;
  Region region;
  std::optional<Region> reinsert;
  SourceLoc loc, reinsert_loc;
};

/// A flow meter: the grains whose centres cross a plane (through `point`, unit `normal`; in 2D
/// a line of the plane) between two steps, counted net: +1 and +m along the normal, -1 and -m
/// against it; with `radius`, only crossings within that distance of `point` (a disk; in 2D a
/// segment). Fixed grains are never counted; a grain inserted or put back by an outlet starts
/// where it is placed (the jump is no crossing). LIGGGHTS: fix massflow/mesh.
struct FlowMeter {
  std::string name;
  Vec3 point;
  Vec3 normal{0, 0, 1};
  std::optional<double> radius;  ///< m; none: the whole plane
  SourceLoc loc;
};

/// A named region for the series (region_count, region_mass: the free grains whose centres
/// lie in it, e.g. the hold-up of a hopper).
struct NamedRegion {
  std::string name;
  Region region;
  SourceLoc loc;
};

struct Fill {
  Region region;
  enum class Lattice { Cubic, Hcp, Random };
  Lattice lattice = Lattice::Cubic;
  std::optional<double> spacing;      ///< lattice spacing, m (default: 2 r_max * 1.01)
  std::optional<std::int64_t> count;  ///< cap (lattice) or target (random)
  /// Target volume fraction of the region (2D: area fraction) instead of a count: the count is
  /// round(fraction x region volume / grain volume) (fixed sizes only), and a lattice fill then
  /// takes that many of its sites at random, so that the density is uniform over the region.
  std::optional<double> volume_fraction;
  std::uint64_t seed = 1;
  Vec3 velocity;                  ///< initial velocity, m/s
  double velocity_jitter = 0;     ///< uniform random perturbation amplitude, m/s
  std::int64_t max_attempts = 0;  ///< random: insertion attempts (0 = 1000 * count)
  /// Orientation of non-spherical grains: nullopt = uniformly random (3D: axis uniform on the
  /// sphere; 2D: angle uniform in [0, 2 pi)); otherwise this one for all (from `orientation:
  /// {axis: [...]}` in 3D, the rotation taking e_z to the axis, or `{angle: a}` in 2D).
  std::optional<Quat> orientation;
  SourceLoc loc;  ///< the `fill:` block, for messages
  /// Where the keys that set the number of grains are (empty when not given): `count` or
  /// `volume_fraction`, `spacing`, and the region (`box` / `cylinder`), for the memory check.
  SourceLoc count_loc, spacing_loc, region_loc;
};

/// Explicit particles; vectors have one entry per particle (velocities etc. may be empty = zero).
struct Explicit {
  std::vector<Vec3> positions;
  std::vector<Vec3> velocities;
  std::vector<Vec3> angular_velocities;
  std::vector<Quat> orientations;  ///< empty = identity; from `axes:` (3D, rotation taking e_z
                                   ///< to the axis) or `angles:` (2D, rad about z)
  std::vector<double> radii;       ///< from a CSV 'radius' column; empty = the group's radius
  std::filesystem::path file;      ///< CSV source, if any (already read into the vectors)
  std::vector<int> lines;          ///< 1-based line of each particle in the case file or CSV
};

/// Polygon grains (2D): given vertices, regular n-gons or random irregular convex polygons.
struct PolygonSpec {
  enum class Kind { Vertices, Regular, Random };
  Kind kind = Kind::Regular;
  /// Vertices: convex, counter-clockwise, m (z = 0); the simulation recentres them on their
  /// centroid. The group's radius is then not used (it is the equal-area radius of these).
  std::vector<Vec3> vertices;
  int sides = 6;  ///< Regular: number of vertices (3..16); size = equal-area radius `radius`
  /// Random: vertex count uniform in [min_vertices, max_vertices] (3..16), elongation (aspect
  /// ratio of the ellipse the vertices lie on, >= 1) uniform in [min_elongation,
  /// max_elongation]; size = equal-area radius drawn from `radius`.
  int min_vertices = 5, max_vertices = 8;
  double min_elongation = 1.0, max_elongation = 1.0;
};

/// Shapes: sphere (3D), spherocylinder (3D), disk (2D), polygon (2D).
enum class Shape { Sphere, Spherocylinder, Disk, Polygon };

/// Prescribed rigid motion (walls[].motion, and fixed particle groups): a translation at
/// `velocity` from `start` on and a rotation about `axis` through `center` from t = 0.
struct Motion {
  Vec3 velocity;     ///< translation, m/s
  double start = 0;  ///< s: the translation begins at this time (the wall rests before)
  bool rotates = false;
  Vec3 axis{0, 0, 1};  ///< unit rotation axis
  Vec3 center;         ///< a point on the rotation axis at t = 0, m
  double rate = 0;     ///< rad/s (from `rpm` or `rate`)
};

/// A particle group's inlet: grains of the group (spheres, disks, spherocylinders; the latter
/// randomly oriented, placed by the sphere that holds any of them) inserted during the run
/// at `rate` grains per second, in batches every `every` seconds from `start` to `stop`, each at
/// a uniformly random place of `region` where it overlaps no grain, with `velocity`. A batch at
/// time t inserts the grains due by t + every (so the first one, at `start`, rate x every).
struct Inlet {
  Region region;
  double rate = 0;                  ///< grains per second (0 with a mass_rate)
  std::optional<double> mass_rate;  ///< kg/s instead of a count: grains until the mass is due
  Vec3 velocity;                    ///< m/s
  double start = 0;                 ///< s
  std::optional<double> stop;       ///< s; none: to the end of the run
  double every = 0.01;              ///< s between batches
  SourceLoc loc, rate_loc;
};

struct ParticleGroup {
  std::string shape = "sphere";  ///< as written; `kind` is the parsed value
  Shape kind = Shape::Sphere;
  /// sphere, disk: the radius; spherocylinder: the radius r of the caps and cylinder (from
  /// `equivalent_diameter` and `aspect_ratio` when given that way); polygon: the radius of the
  /// equal-area disk.
  SizeDistribution radius;
  /// Spherocylinder: exactly one of these is set after parsing. `length` is the length L of the
  /// cylindrical part (m, >= 0); `aspect_ratio` = (L + 2r)/(2r) >= 1 (total length over
  /// diameter), so that L follows each grain's radius when the radius is a distribution.
  std::optional<double> length;
  std::optional<double> aspect_ratio;
  PolygonSpec polygon;  ///< polygon only
  std::string material;
  std::optional<Fill> fill;
  std::optional<Explicit> explicit_particles;
  std::optional<Inlet> inlet;  ///< grains inserted during the run (the group starts empty)
  /// `fixed: true`: the grains never move (a rough base, an obstacle made of grains): they keep
  /// their initial position and orientation with zero velocity and angular velocity, are never
  /// integrated, count as infinitely heavy in their contacts with free grains, and touch neither
  /// one another nor walls (docs/models/fixed_particles.md). Initial velocities are refused.
  bool fixed = false;
  /// `fixed: {translate: ..., rotate: ...}` (the keys of walls[].motion): a fixed group whose
  /// grains follow this prescribed rigid motion instead of resting (fixed is then true); none:
  /// at rest.
  std::optional<Motion> motion;
  /// Initial temperature of the group's grains, K (heat: block; default heat.temperature).
  std::optional<double> temperature;
  /// Heat each grain of the group produces, W (heat: block; negative: a sink); none: 0.
  std::optional<double> heat_source;
  SourceLoc fixed_loc;  ///< where the value of `fixed:` is (empty without the key)
  SourceLoc loc;
};

/// Stress-controlled (servo) plane wall: it moves along its normal so that the particles push
/// on it with pressure * area, area = the product of the distances between the named pairs of
/// walls (each pair two parallel planes), times domain.thickness in 2D.
struct Servo {
  double pressure = 0;      ///< Pa
  double max_velocity = 0;  ///< m/s: speed when the force is 0 (and the limit)
  std::vector<std::array<std::string, 2>> spans;  ///< 2D: one pair, 3D: two pairs
  std::optional<double> until;                    ///< s: control stops (the wall rests) after
  double gain = 0.01;  ///< fraction of the force error corrected per step (Wall::servo_step)
  SourceLoc loc;
};

struct Wall {
  std::string name;
  enum class Kind { Plane, Box, Cylinder, Mesh };
  Kind kind = Kind::Plane;
  // Plane
  Vec3 point, normal{0, 0, 1};  ///< normal points to the side where particles are
  // Box: inward-facing planes on the faces not listed in `open` (xmin, xmax, ymin, ...)
  Vec3 min, max;
  std::vector<std::string> open;
  // Cylinder (infinite unless bounded)
  Vec3 center;         ///< a point on the axis
  Vec3 axis{0, 0, 1};  ///< unit axis
  double radius = 0;
  bool inside = true;  ///< particles inside the cylinder (drum) or outside (post)
  // Mesh: an STL file (ASCII or binary), its vertices scaled then offset (x_case = scale x_file
  // + offset); the triangles read with the case (degenerate ones dropped and counted).
  std::filesystem::path mesh_file;  ///< absolute
  double mesh_scale = 1;
  Vec3 mesh_offset;
  std::vector<Vec3> mesh_points;                   ///< m, in the case's frame
  std::vector<std::array<int, 3>> mesh_triangles;  ///< indices into mesh_points
  std::size_t mesh_dropped = 0;                    ///< degenerate triangles left out
  std::string material;
  Motion motion;
  std::optional<Servo> servo;  ///< plane walls only
  /// Temperature of the wall's surface, K (heat: block); none: adiabatic.
  std::optional<double> temperature;
  bool from_shear = false;  ///< generated by the `shear:` block (not echoed as a wall)
  SourceLoc loc;
};

/// Simple shear: flow along x, velocity gradient along z, apparent shear rate `rate`.
///   walls: two plane walls at z = min and z = max (named shear_bottom, shear_top) moving at
///          -rate h/2 and +rate h/2 along x (h the box height); x and y periodic;
///   lees_edwards: no walls; periodic in x, y, z with sliding images along z (core/domain.hpp).
struct Shear {
  enum class Boundary { Walls, LeesEdwards };
  double rate = 0;  ///< 1/s
  Boundary boundary = Boundary::Walls;
  std::string wall_material;     ///< walls: material of the two walls
  std::optional<double> strain;  ///< total strain; sets time.end = strain / rate
  bool initial_profile = true;   ///< start the grains on the mean flow u_x = rate (z - z_mid)
  SourceLoc loc;
};

/// Rheology measurements (analysis/rheology.hpp), sampled every `every` seconds.
struct Rheology {
  double every = 0;  ///< s (from `every`, or `every_strain` / shear.rate)
  std::optional<double> every_strain;
  int bins = 16;                 ///< layers along z for the mean velocity profile
  std::optional<double> margin;  ///< m, excluded next to each wall; default one grain length
  std::optional<double> start;   ///< s, start of the steady-state average; default automatic
  SourceLoc loc;
};

/// The Lacey mixing index of two kinds of grains (analysis/mixing.hpp), for the series
/// quantity lacey_index: the grains of `materials[0]` against those of `materials[1]`.
struct Mixing {
  std::vector<std::string> materials;  ///< two material names
  double cell = 0;                     ///< m, side of the cubic (2D: square) cells
  int min_grains = 5;                  ///< cells with fewer grains are not counted
  SourceLoc loc;
};

struct Analysis {
  std::optional<Rheology> rheology;
  std::optional<Mixing> mixing;
};

/// A sweep over volume fractions and shear rates (grainflow sweep): every combination runs as
/// its own case (fill.volume_fraction and shear.rate replaced) in its own folder.
struct Sweep {
  std::vector<double> volume_fractions;
  std::vector<double> shear_rates;
  int processes = 0;  ///< 0: as many as cores
  SourceLoc loc;
};

/// Condition on one face of the fluid grid's box (fluid.boundary.xmin ...).
struct FluidBoundary {
  enum class Kind { Periodic, NoSlip, MovingWall, VelocityInlet, PressureOutlet };
  Kind kind = Kind::NoSlip;
  Vec3 velocity;        ///< moving_wall: wall velocity; velocity_inlet: superficial velocity, m/s
  double pressure = 0;  ///< pressure_outlet: static pressure, Pa
  bool given = false;   ///< written in the case (else the default: periodic or no_slip)
  /// With coupling.heat_transfer: the inflow's temperature (inlets, required), the wall's
  /// (walls; none: adiabatic) or the back-flow's (outlets; none: the cell's), K
  std::optional<double> temperature;
  SourceLoc loc;  ///< the face's entry, when given
};

/// The interstitial fluid of unresolved CFD-DEM (src/fluid/fv): a uniform Cartesian grid over
/// the DEM domain box.
struct Fluid {
  double density = 0;    ///< kg/m^3
  double viscosity = 0;  ///< dynamic, Pa s
  std::array<int, 3> cells{1, 1, 1};
  /// Indexed like gf::fluid::box_face_index: xmin, xmax, ymin, ymax, zmin, zmax. Faces not given
  /// are periodic on periodic axes of the domain, no_slip otherwise.
  std::array<FluidBoundary, 6> boundary{};
  Vec3 initial_velocity;                ///< m/s
  std::string convection = "van_leer";  ///< van_leer | central | upwind
  /// The fluid's temperature (with coupling.heat_transfer): c_p [J/(kg K)], k [W/(m K)] (0: not
  /// given) and the initial temperature [K] (none: heat.temperature)
  double heat_capacity = 0, thermal_conductivity = 0;
  std::string temperature_convection = "van_leer";  ///< van_leer | upwind
  /// Boussinesq buoyancy: beta [1/K] (0: none) about the reference temperature [K] (none: the
  /// fluid's initial temperature)
  double thermal_expansion = 0;
  std::optional<double> reference_temperature;
  std::optional<double> temperature;
  std::optional<SourceLoc> thermal_loc;  ///< the first of these keys given, for errors
  SourceLoc loc;
  SourceLoc cells_loc;  ///< the value of `cells`
};

/// Particle-fluid coupling (docs/models/cfd_dem.md).
struct Coupling {
  std::string drag;  ///< drag registry key (coupling/cfd_dem/drag_registry)
  std::map<std::string, double> drag_params;  ///< the law's parameters as given (defaults: none)
  std::string fluid_fraction = "divided";     ///< centre | divided | trilinear | smoothed
  int interval = 100;                         ///< DEM steps per fluid step
  double min_fraction = 0.3;                  ///< lower clamp of the fluid fraction
  /// d eps/dt in the fluid's continuity: "flux" (divergence of the grains' solid volume flux),
  /// "difference" (change of the deposited eps over the fluid step) or "derivative" (the time
  /// derivative of a continuous deposit; fluid_fraction: trilinear or smoothed only)
  std::string fluid_fraction_rate = "flux";
  /// Under-relaxation a of the flux rate between fluid steps: rate = rate_prev + a (new - prev)
  double rate_relaxation = 0.3;
  /// Whether each grain also feels -V_i grad p (the pressure-gradient force of model A, which
  /// carries buoyancy); false: drag only (as in Mahajan et al.'s shear boxes)
  bool pressure_gradient_force = true;
  /// How grains read the fluid's velocity, fraction and pressure gradient: "trilinear" between
  /// cell centres or "cell" (the value of the cell containing the grain's centre)
  std::string interpolation = "trilinear";
  /// Hydrodynamic torque on the grains: "none" (Mahajan et al.'s shear boxes) or "rotational"
  /// (viscous resistance to rotating relative to the fluid's curl(u) / 2; Stokes with Dennis et
  /// al.'s inertia factor, coupling/cfd_dem/hydro_torque.hpp)
  std::string torque = "none";
  /// Convective heat exchange of grains and fluid: a Nusselt correlation of
  /// coupling/cfd_dem/heat_transfer.hpp, or empty (none; the fluid has no temperature)
  std::string heat_transfer;
  SourceLoc loc;
};

struct OutputEvery {
  double every = 0;  ///< s; 0 = disabled (from every_strain / shear.rate if given)
  std::optional<double> every_strain;  ///< the interval as given in strain (shear cases)
};

struct Output {
  std::filesystem::path directory = "out";
  OutputEvery vtk, particles_csv, contacts_csv, contacts_vtk, checkpoint;
  OutputEvery series{};
  std::vector<std::string> quantities;  ///< series quantities, validated against the known list
};

struct Neighbor {
  std::optional<double> skin;  ///< m; default 0.25 x the largest diameter
};

/// Heat conduction through the contacts (`heat:`): the conductance model (contact/conduction.hpp)
/// and the initial temperature of grains whose group gives none.
struct Heat {
  std::string model = "batchelor_obrien";
  double temperature = 0;  ///< K
  SourceLoc loc;
};

struct Case {
  std::filesystem::path file;  ///< the case file as given
  std::string name;
  int dimension = 3;
  Time time;
  DomainBox domain;
  Vec3 gravity{0, 0, -9.81};
  std::vector<Material> materials;
  std::vector<Contact> contacts;
  std::vector<ParticleGroup> particles;
  std::vector<Wall> walls;
  std::vector<Outlet> outlets;
  std::vector<FlowMeter> flow_meters;
  std::vector<NamedRegion> regions;
  Output output;
  Neighbor neighbor;
  std::string integrator = "velocity_verlet";  ///< velocity_verlet | gear5
  std::optional<Shear> shear;
  Analysis analysis;
  std::optional<Sweep> sweep;
  std::optional<Fluid> fluid;
  std::optional<Coupling> coupling;
  std::optional<Heat> heat;
};

}  // namespace gf::config
