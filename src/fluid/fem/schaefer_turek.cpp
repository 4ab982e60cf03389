// SPDX-License-Identifier: GPL-3.0-or-later
// Setup of the Schaefer & Turek (1996) cylinder benchmark on a CGAL mesh.
#include "fluid/fem/schaefer_turek.hpp"

namespace gf::fem::schaefer_turek {

FlowProblem make_problem(const MeshLevel& level, double u_max, std::function<double(double)> f) {
  FlowProblem pb;
  pb.spec.outline = {{0, 0}, {kLength, 0}, {kLength, kHeight}, {0, kHeight}};
  BodyShape cyl;
  cyl.kind = BodyShape::Kind::Circle;
  cyl.centre = {kCx, kCy};
  cyl.radius = kDiameter / 2;
  pb.spec.bodies = {cyl};
  pb.spec.h_max = level.h_max;
  pb.spec.h_body = level.h_body;
  pb.spec.grading = level.grading;
  pb.spec.min_angle_deg = 28;
  if (level.h_wake > 0) pb.spec.boxes.push_back({{0.15, 0.05}, {1.2, 0.36}, level.h_wake});
  pb.mesh = build_mesh(pb.spec);
  pb.density = 1.0;
  pb.viscosity = 1e-3;
  OutlineBc wall, out, in;
  wall.kind = OutlineBcKind::Wall;
  out.kind = OutlineBcKind::Outflow;
  in.kind = OutlineBcKind::Inflow;
  in.u_max = u_max;
  in.time_function = std::move(f);
  pb.outline_bc = {wall, out, wall, in};
  pb.body_motion.resize(1);
  return pb;
}

Coefficients coefficients(const NavierStokes& ns, const BodyForce& f, double ubar) {
  const double s = 2.0 / (ns.problem().density * ubar * ubar * kDiameter);
  return {s * f.force.x, s * f.force.y,
          ns.pressure_at({kCx - kDiameter / 2, kCy}) - ns.pressure_at({kCx + kDiameter / 2, kCy})};
}

}  // namespace gf::fem::schaefer_turek
