// SPDX-License-Identifier: GPL-3.0-or-later
// Whole-case cross-checks (domain, overlaps, time step vs contact times) and derived numbers.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/input/config.hpp"

namespace gf::input {

/// What `grainflow check` prints besides errors.
struct CheckReport {
  /// Human-readable derived numbers, in order: (what, value with unit).
  std::vector<std::pair<std::string, std::string>> derived;
  /// Things that are allowed but probably not meant.
  std::vector<std::string> warnings;
};

/// Checks what needs several blocks of the case at once and throws gf::InputError (with the
/// file:line:column of the culprit) on the first failure:
///  - every referenced material exists and every used material pair has a contacts entry;
///  - explicit particles lie inside the domain and do not overlap one another (cell method on
///    the bounding radii, then the shapes: sphere / disk radii, spherocylinder axis segments,
///    polygon outlines; random polygons, drawn at run time, only by their centres, with a
///    warning for pairs whose bounding circles intersect); grains of fixed groups (fixed: true)
///    may overlap one another, since they never touch;
///  - fill regions lie inside the domain; periodic lengths exceed 2 (2 r_max + skin), r_max the
///    largest bounding radius; in 2D only x and y are checked;
///  - the time step is at most 0.3 x min(Rayleigh time, contact time) (warning above 0.15 x).
///    The Rayleigh time (smallest grain of each material; contact radius: sphere / disk radius,
///    spherocylinder cap radius, polygon equal-area radius) counts for materials whose contacts
///    use elastic moduli (every model except hooke, whose stiffness is given directly); the
///    contact time is computed for every used pair with the smallest grain of each group (its
///    contact radius and its mass, from grain_measure and, in 2D, the domain's thickness), at an
///    impact speed max(initial speeds) + sqrt(2 |g| H), H the domain height along gravity,
///    >= 0.1 m/s. Fixed groups: a free grain meets a fixed one at that speed (not twice) with
///    m* its own mass (contact::reduced_mass); pairs of fixed grains and fixed grains with walls
///    never touch and are left out, as are fixed grains from the Rayleigh time;
///  - for each such pair with sjkr cohesion (k_c > 0), a derived row with the resting overlap
///    over the radius of two equal grains (or one on a wall) at rest with no other load
///    (contact::equilibrium_overlap, at the smallest and the largest radius present, the larger
///    ratio reported), and a warning above 0.1 or where cohesion always wins.
CheckReport validate(const config::Case& c);

/// Length L of the cylindrical part of a spherocylinder of cap radius r (m): `length`, or
/// 2 r (aspect_ratio - 1); 0 for the other shapes.
double cylinder_length(const config::ParticleGroup& g, double r);

/// Ratio of a polygon's circumradius (about its centroid) to its equal-area radius. Vertices:
/// exact; regular n-gon: sqrt(2 pi / (n sin(2 pi / n))); random: the largest ratio of ~2000
/// polygons drawn from the generator, plus 5 %. The simulation redraws the rare outline beyond
/// it (simulation/shape_builder.cpp), so it bounds every grain of a run.
double polygon_reach_factor(const config::PolygonSpec& p);

/// Radius (m) of the sphere (3D) or disk (2D) about a grain's centre that contains the grain, for
/// a grain of group g with radius r (sphere, disk: r; spherocylinder: r + L/2; polygon: its
/// circumradius, r x polygon_reach_factor, or from the vertices).
double bounding_radius(const config::ParticleGroup& g, double r);

/// Volume (3D, m^3) or area (2D, m^2) of one grain of group g with radius r: sphere 4/3 pi r^3,
/// spherocylinder pi r^2 L + 4/3 pi r^3, disk pi r^2, polygon pi R^2 (R the equal-area radius;
/// the shoelace area for given vertices).
double grain_measure(const config::ParticleGroup& g, double r);

/// Half extents along x, y, z of a grain of group g with radius r as a fill places it: the
/// bounding box of a spherocylinder of the fill's fixed orientation, else the bounding radius.
Vec3 grain_extent(const config::Fill& f, const config::ParticleGroup& g, double r);

/// Volume (3D) or area (2D) of a fill region, m^3 or m^2.
double region_measure(const config::Region& region, int dimension);

/// Axis-aligned bounds {lo, hi} of a region (a cylinder: of its disc swept along the axis).
std::pair<Vec3, Vec3> region_bounds(const config::Region& region);

/// Grains of a fill: round(volume_fraction x region measure / grain measure) when the fill
/// gives a volume fraction, else its count (0 when none).
std::int64_t volume_fraction_count(const config::Fill& f, const config::ParticleGroup& g,
                                   int dimension);

}  // namespace gf::input
