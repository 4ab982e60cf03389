// SPDX-License-Identifier: GPL-3.0-or-later
// case.yaml -> config::Case: one function per block, each key checked for type, range and place.
#include "io/input/parse_case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>

#include "contact/registry.hpp"
#include "core/error.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

namespace fs = std::filesystem;

namespace {

std::string vec_text(const Vec3& v) {
  return fmt::format("[{}, {}, {}]", number_text(v.x), number_text(v.y), number_text(v.z));
}

/// State shared by the block readers.
struct Reader {
  fs::path case_dir;
  config::Case& c;
  /// Where each material was first referenced by a particle group / wall (for missing pairs).
  std::map<std::string, config::SourceLoc> particle_material_ref;
  std::vector<std::string> particle_materials;  ///< in order of first use
  std::vector<std::pair<std::string, config::SourceLoc>> wall_material_refs;

  std::vector<std::string> material_names() const {
    std::vector<std::string> out;
    for (const auto& m : c.materials) out.push_back(m.name);
    return out;
  }

  /// Reads a material reference and checks that it is defined.
  std::string material_ref(const YamlNode& n) const {
    const std::string name = n.as_string();
    for (const auto& m : c.materials)
      if (m.name == name) return name;
    const auto names = material_names();
    std::string hint;
    if (auto near = closest_match(name, names)) hint = fmt::format(" (did you mean '{}'?)", *near);
    n.fail(fmt::format("unknown material '{}'{}; defined materials: {}", name, hint, join(names)));
  }

  void read_time(const YamlMap& root);
  void read_domain(const YamlMap& root);
  void read_materials(const YamlMap& root);
  void read_contacts(const YamlMap& root);
  void read_particles(const YamlMap& root);
  config::ParticleGroup read_group(const YamlNode& node);
  config::SizeDistribution read_radius(const YamlNode& node);
  config::Fill read_fill(const YamlNode& node, const config::SizeDistribution& radius);
  void read_positions(const YamlMap& gm, config::Explicit& ex);
  std::vector<double> read_csv(const YamlNode& file_node, config::Explicit& ex);
  void read_walls(const YamlMap& root);
  config::Motion read_motion(const YamlNode& node);
  void read_output(const YamlMap& root);
  void check_pairs() const;
};

void Reader::read_time(const YamlMap& root) {
  YamlMap t(root.at("time"), {"step", "end"});
  c.time.step = t.number("step", Range::positive());
  c.time.end = t.number("end", Range::positive());
  if (c.time.end < c.time.step)
    t.at("end").fail_expected(fmt::format("a number >= time.step ({})", number_text(c.time.step)));
  c.time.loc = t.at("step").loc();
}

void Reader::read_domain(const YamlMap& root) {
  const YamlNode dn = root.at("domain");
  YamlMap d(dn, {"min", "max", "periodic"});
  c.domain.min = d.vec3("min");
  c.domain.max = d.vec3("max");
  for (int k = 0; k < 3; ++k) {
    if (!(c.domain.max[k] > c.domain.min[k]))
      d.at("max").fail_expected(fmt::format("every component greater than that of domain.min {}",
                                            vec_text(c.domain.min)));
  }
  if (auto p = d.find("periodic")) {
    if (!p->is_list() || p->raw().size() != 3) p->fail_expected("a list of 3 booleans [x, y, z]");
    const auto items = p->as_list();
    for (int k = 0; k < 3; ++k) c.domain.periodic[k] = items[k].as_bool();
  }
  c.domain.loc = dn.loc();
}

void Reader::read_materials(const YamlMap& root) {
  const YamlNode mn = root.at("materials");
  YamlMap m(mn);
  const auto entries = m.entries();
  if (entries.empty())
    mn.fail_expected("at least one material 'name: {density, youngs_modulus, poisson_ratio}'");
  for (const auto& [key, value] : entries) {
    config::Material mat;
    mat.name = key.as_string();
    if (mat.name.empty()) key.fail_expected("a material name");
    YamlMap mm(value, {"density", "youngs_modulus", "poisson_ratio"});
    mat.density = mm.number("density", Range::positive());
    mat.youngs_modulus = mm.number("youngs_modulus", Range::positive());
    mat.poisson_ratio = mm.number("poisson_ratio", Range{-1.0, 0.5, true, true});
    mat.loc = value.loc();
    c.materials.push_back(mat);
  }
}

/// Models whose schema lists required parameters that may be replaced by others: each inner list
/// is one complete alternative.
std::vector<std::vector<std::string>> param_alternatives(std::string_view model) {
  if (model == "hooke") return {{"stiffness"}, {"max_overlap", "reference_velocity"}};
  return {};
}

void Reader::read_contacts(const YamlMap& root) {
  auto cn = root.find("contacts");
  if (!cn) return;
  std::map<std::pair<std::string, std::string>, int> seen;  // pair -> line
  for (const auto& item : cn->as_list()) {
    YamlMap cm(item);
    config::Contact ct;
    ct.loc = item.loc();
    const YamlNode between = cm.at("between");
    if (!between.is_list() || between.raw().size() != 2)
      between.fail_expected("a list of 2 material names [a, b]");
    const auto names = between.as_list();
    ct.between = {material_ref(names[0]), material_ref(names[1])};
    const auto key = std::minmax(ct.between[0], ct.between[1]);
    if (auto it = seen.find(key); it != seen.end())
      between.fail(fmt::format("the pair ({}, {}) already has a contacts entry (line {})",
                               key.first, key.second, it->second));
    seen.emplace(key, between.line());

    const YamlNode model = cm.at("model");
    ct.model = model.as_string();
    const contact::ModelInfo* info = contact::find_model(ct.model);
    if (!info) {
      std::vector<std::string> keys;
      for (const auto& mi : contact::model_infos()) keys.emplace_back(mi.key);
      std::string hint;
      if (auto near = closest_match(ct.model, keys))
        hint = fmt::format(" (did you mean '{}'?)", *near);
      model.fail(fmt::format("unknown contact model '{}'{}; registered models: {}", ct.model, hint,
                             join(keys)));
    }
    std::vector<std::string> param_names;
    for (const auto& p : info->params) param_names.emplace_back(p.name);
    std::vector<std::string> accepted{"between", "model"};
    accepted.insert(accepted.end(), param_names.begin(), param_names.end());
    for (const auto& [k, v] : cm.entries()) {
      const std::string name = k.as_string();
      if (std::find(accepted.begin(), accepted.end(), name) != accepted.end()) continue;
      std::string hint;
      if (auto near = closest_match(name, accepted))
        hint = fmt::format(" (did you mean '{}'?)", *near);
      k.fail(
          fmt::format("unknown parameter '{}'{} of contact model '{}'; its parameters: {} (besides "
                      "between, model)",
                      name, hint, ct.model, join(param_names)));
    }
    const auto alternatives = param_alternatives(ct.model);
    auto in_alternative = [&](std::string_view name) {
      for (const auto& alt : alternatives)
        if (std::find(alt.begin(), alt.end(), name) != alt.end()) return true;
      return false;
    };
    for (const auto& p : info->params) {
      if (auto v = cm.find(p.name)) {
        ct.params[std::string(p.name)] = v->as_number(Range{p.min, p.max, p.min_exclusive, false});
      } else if (p.default_value) {
        ct.params[std::string(p.name)] = *p.default_value;
      } else if (!in_alternative(p.name)) {
        config::SourceLoc loc = item.loc();
        loc.key_path = fmt::format("{}.{}", item.path(), p.name);
        throw_input_error(
            loc, fmt::format("missing required key '{}' of contact model '{}' ({}, {})", p.name,
                             ct.model, p.description, p.unit == "1" ? "dimensionless" : p.unit));
      }
    }
    if (!alternatives.empty()) {
      std::size_t n_complete = 0, n_touched = 0;  // alternatives given fully / at least in part
      for (const auto& alt : alternatives) {
        std::size_t n_given = 0;
        for (const auto& n : alt) n_given += cm.has(n) ? 1 : 0;
        n_complete += n_given == alt.size() ? 1 : 0;
        n_touched += n_given > 0 ? 1 : 0;
      }
      if (n_complete != 1 || n_touched != 1) {
        std::vector<std::string> forms, given;
        for (const auto& alt : alternatives) {
          std::vector<std::string> quoted;
          for (const auto& n : alt) {
            quoted.push_back(fmt::format("'{}'", n));
            if (cm.has(n)) given.push_back(n);
          }
          forms.push_back(join(quoted, " and "));
        }
        config::SourceLoc loc = item.loc();
        loc.key_path = fmt::format("{}.{}", item.path(), alternatives.front().front());
        throw_input_error(
            loc, fmt::format("contact model '{}' needs exactly one of: {}; found {}", ct.model,
                             join(forms, ", or "), given.empty() ? "none" : join(given)));
      }
    }
    c.contacts.push_back(std::move(ct));
  }
}

config::SizeDistribution Reader::read_radius(const YamlNode& node) {
  config::SizeDistribution d;
  if (node.is_scalar()) {
    d.kind = config::SizeDistribution::Kind::Fixed;
    d.value = node.as_number(Range::positive());
    return d;
  }
  if (!node.is_map())
    node.fail_expected(
        "a radius in m (a number > 0) or a map {distribution: uniform|normal|lognormal, ...}");
  YamlMap rm(node, {"distribution", "min", "max", "mean", "std"});
  const std::string kind = rm.at("distribution").as_choice({"uniform", "normal", "lognormal"});
  d.min = rm.number("min", Range::positive());
  d.max = rm.number("max", Range::positive());
  if (!(d.max > d.min))
    rm.at("max").fail_expected(fmt::format("a number > min ({})", number_text(d.min)));
  if (kind == "uniform") {
    d.kind = config::SizeDistribution::Kind::Uniform;
    for (const char* k : {"mean", "std"})
      if (auto n = rm.find(k))
        n->fail(fmt::format("'{}' does not apply to distribution: uniform (min, max only)", k));
    return d;
  }
  d.kind = kind == "normal" ? config::SizeDistribution::Kind::Normal
                            : config::SizeDistribution::Kind::Lognormal;
  d.mean = rm.number("mean", Range::positive());
  d.std = rm.number("std", Range::positive());
  if (!(d.mean > d.min && d.mean < d.max))
    rm.at("mean").fail_expected(fmt::format("a number between min ({}) and max ({})",
                                            number_text(d.min), number_text(d.max)));
  return d;
}

config::Fill Reader::read_fill(const YamlNode& node, const config::SizeDistribution& radius) {
  config::Fill f;
  YamlMap fm(node, {"box", "cylinder", "lattice", "spacing", "count", "seed", "velocity",
                    "velocity_jitter", "max_attempts"});
  f.loc = node.loc();
  const std::string region = fm.exactly_one_of({"box", "cylinder"});
  if (region == "box") {
    YamlMap bm(fm.at("box"), {"min", "max"});
    f.region.kind = config::Region::Kind::Box;
    f.region.min = bm.vec3("min");
    f.region.max = bm.vec3("max");
    for (int k = 0; k < 3; ++k)
      if (!(f.region.max[k] > f.region.min[k]))
        bm.at("max").fail_expected(
            fmt::format("every component greater than that of min {}", vec_text(f.region.min)));
  } else {
    YamlMap cm(fm.at("cylinder"), {"center", "axis", "radius", "height"});
    f.region.kind = config::Region::Kind::Cylinder;
    f.region.center = cm.vec3("center");
    if (auto a = cm.find("axis")) f.region.axis = a->as_direction();
    f.region.radius = cm.number("radius", Range::positive());
    f.region.height = cm.number("height", Range::positive());
  }
  if (auto l = fm.find("lattice")) {
    const std::string s = l->as_choice({"cubic", "hcp", "random"});
    f.lattice = s == "cubic" ? config::Fill::Lattice::Cubic
                : s == "hcp" ? config::Fill::Lattice::Hcp
                             : config::Fill::Lattice::Random;
  }
  const bool random = f.lattice == config::Fill::Lattice::Random;
  if (auto s = fm.find("spacing")) {
    if (random)
      s->fail("'spacing' applies to the cubic and hcp lattices only, not to lattice: random");
    const double min_spacing = 2 * radius.largest();
    f.spacing = s->as_number(Range::positive());
    if (*f.spacing < min_spacing)
      s->fail_expected(
          fmt::format("a spacing >= 2 x the largest radius ({} m) so that grains do not overlap",
                      number_text(min_spacing)));
  }
  if (auto n = fm.find("count")) {
    f.count = n->as_integer(Range::at_least(1));
  } else if (random) {
    config::SourceLoc loc = node.key_loc();
    loc.key_path = node.path() + ".count";
    throw_input_error(
        loc, "missing required key 'count' (lattice: random needs the number of grains to insert)");
  }
  if (auto s = fm.find("seed"))
    f.seed = static_cast<std::uint64_t>(s->as_integer(Range::non_negative()));
  f.velocity = fm.vec3_or("velocity", Vec3{});
  f.velocity_jitter = fm.number_or("velocity_jitter", 0.0, Range::non_negative());
  if (auto m = fm.find("max_attempts")) {
    if (!random) m->fail("'max_attempts' applies to lattice: random only");
    f.max_attempts = m->as_integer(Range::at_least(1));
  }
  return f;
}

void Reader::read_positions(const YamlMap& gm, config::Explicit& ex) {
  const auto items = gm.at("positions").as_list(1);
  for (const auto& it : items) {
    ex.positions.push_back(it.as_vec3());
    ex.lines.push_back(it.line());
  }
  auto read_same_length = [&](const char* key, std::vector<Vec3>& out) {
    auto n = gm.find(key);
    if (!n) return;
    if (!n->is_list() || n->raw().size() != items.size())
      n->fail_expected(
          fmt::format("a list of {} [x, y, z] entries (one per position)", items.size()));
    for (const auto& it : n->as_list()) out.push_back(it.as_vec3());
  };
  read_same_length("velocities", ex.velocities);
  read_same_length("angular_velocities", ex.angular_velocities);
}

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

/// Fields of one CSV line with their 1-based start columns.
std::vector<std::pair<std::string_view, int>> split_csv(std::string_view line) {
  std::vector<std::pair<std::string_view, int>> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string_view raw =
        line.substr(start, comma == std::string_view::npos ? line.npos : comma - start);
    std::size_t lead = 0;
    while (lead < raw.size() && (raw[lead] == ' ' || raw[lead] == '\t')) ++lead;
    out.emplace_back(trim(raw), static_cast<int>(start + lead) + 1);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

std::vector<double> Reader::read_csv(const YamlNode& file_node, config::Explicit& ex) {
  const std::string given = file_node.as_string();
  if (given.empty()) file_node.fail_expected("a CSV file name");
  fs::path path =
      fs::path(given).is_absolute() ? fs::path(given) : (case_dir / given).lexically_normal();
  ex.file = path;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    file_node.fail(fmt::format("cannot open the particle file '{}'{}", path.string(),
                               fs::exists(path) ? "" : " (no such file)"));
  const std::string key_path = file_node.path();
  auto fail_at = [&](int line, int column, const std::string& msg) {
    config::SourceLoc loc{path.string(), line, column, key_path};
    throw_input_error(loc, msg);
  };

  static const std::vector<std::string> known{"x",  "y",  "z",  "vx", "vy",
                                              "vz", "wx", "wy", "wz", "radius"};
  std::vector<int> column_of;  // field index -> index in `known`
  std::vector<double> radii;
  std::string line_text;
  int line_no = 0, header_line = 0;
  while (std::getline(in, line_text)) {
    ++line_no;
    const std::string_view line = trim(line_text);
    if (line.empty() || line.front() == '#') continue;
    const auto fields = split_csv(line_text);
    if (header_line == 0) {
      header_line = line_no;
      for (const auto& [name, col] : fields) {
        auto it = std::find(known.begin(), known.end(), name);
        if (it == known.end())
          fail_at(line_no, col,
                  fmt::format("unknown column '{}' in the header; accepted columns: {}", name,
                              join(known)));
        const int idx = static_cast<int>(it - known.begin());
        if (std::find(column_of.begin(), column_of.end(), idx) != column_of.end())
          fail_at(line_no, col, fmt::format("column '{}' appears twice in the header", name));
        column_of.push_back(idx);
      }
      auto has = [&](int idx) {
        return std::find(column_of.begin(), column_of.end(), idx) != column_of.end();
      };
      for (int k = 0; k < 3; ++k)
        if (!has(k))
          fail_at(line_no, 1,
                  fmt::format("expected a header with columns x, y, z (optionally vx, vy, vz, "
                              "wx, wy, wz, radius), found no column '{}'",
                              known[k]));
      for (int g : {3, 6}) {
        const int n = has(g) + has(g + 1) + has(g + 2);
        if (n != 0 && n != 3)
          fail_at(line_no, 1,
                  fmt::format("columns {}, {}, {} go together; found only some of them", known[g],
                              known[g + 1], known[g + 2]));
      }
      continue;
    }
    if (fields.size() != column_of.size())
      fail_at(line_no, 1,
              fmt::format("expected {} comma-separated values (as in the header), found {}",
                          column_of.size(), fields.size()));
    double v[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (std::size_t f = 0; f < fields.size(); ++f) {
      std::string_view text = fields[f].first;
      if (!text.empty() && text.front() == '+') text.remove_prefix(1);
      double x = 0;
      const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
      const int idx = column_of[f];
      if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
          !std::isfinite(x))
        fail_at(
            line_no, fields[f].second,
            fmt::format("column '{}': expected a number, found '{}'", known[idx], fields[f].first));
      if (idx == 9 && !(x > 0))
        fail_at(line_no, fields[f].second,
                fmt::format("column 'radius': expected a number > 0, found '{}'", fields[f].first));
      v[idx] = x;
    }
    ex.positions.push_back({v[0], v[1], v[2]});
    ex.lines.push_back(line_no);
    const bool has_v = std::find(column_of.begin(), column_of.end(), 3) != column_of.end();
    const bool has_w = std::find(column_of.begin(), column_of.end(), 6) != column_of.end();
    const bool has_r = std::find(column_of.begin(), column_of.end(), 9) != column_of.end();
    if (has_v) ex.velocities.push_back({v[3], v[4], v[5]});
    if (has_w) ex.angular_velocities.push_back({v[6], v[7], v[8]});
    if (has_r) radii.push_back(v[9]);
  }
  if (header_line == 0) fail_at(0, 0, "expected a header line 'x,y,z[,...]', found an empty file");
  if (ex.positions.empty())
    fail_at(header_line, 1, "expected particle rows after the header, found none");
  return radii;
}

config::ParticleGroup Reader::read_group(const YamlNode& node) {
  YamlMap gm(node, {"shape", "radius", "material", "fill", "positions", "velocities",
                    "angular_velocities", "file"});
  config::ParticleGroup g;
  g.loc = node.loc();
  if (auto s = gm.find("shape")) {
    g.shape = s->as_string();
    if (g.shape == "spherocylinder" || g.shape == "disk" || g.shape == "polygon")
      s->fail(fmt::format("shape '{}' is not available yet; only sphere is", g.shape));
    if (g.shape != "sphere")
      s->fail_expected("sphere (spherocylinder, disk and polygon are not available yet)");
  }
  const YamlNode mat = gm.at("material");
  g.material = material_ref(mat);
  if (!particle_material_ref.count(g.material)) {
    particle_material_ref[g.material] = mat.loc();
    particle_materials.push_back(g.material);
  }
  const std::string source = gm.exactly_one_of({"fill", "positions", "file"});
  if (source != "positions") {
    for (const char* k : {"velocities", "angular_velocities"}) {
      if (auto n = gm.find(k))
        n->fail(fmt::format("'{}' go with 'positions:'{}", k,
                            source == "file"
                                ? " (a CSV file gives them as columns vx,vy,vz / wx,wy,wz)"
                                : " (a fill gives 'velocity' inside 'fill:')"));
    }
  }
  if (source == "file") {
    config::Explicit ex;
    const auto radii = read_csv(gm.at("file"), ex);
    if (!radii.empty()) {
      if (auto r = gm.find("radius"))
        r->fail(fmt::format(
            "the particle file '{}' has a radius column; give the radius in one place only",
            ex.file.string()));
      const auto [lo, hi] = std::minmax_element(radii.begin(), radii.end());
      if (*lo == *hi) {
        g.radius.kind = config::SizeDistribution::Kind::Fixed;
        g.radius.value = *lo;
      } else {
        g.radius.kind = config::SizeDistribution::Kind::Uniform;  // bounds of the radii read
        g.radius.min = *lo;
        g.radius.max = *hi;
      }
      ex.radii = radii;
    } else {
      g.radius = read_radius(gm.at("radius"));
    }
    g.explicit_particles = std::move(ex);
    return g;
  }
  g.radius = read_radius(gm.at("radius"));
  if (source == "fill") {
    g.fill = read_fill(gm.at("fill"), g.radius);
  } else {
    config::Explicit ex;
    read_positions(gm, ex);
    g.explicit_particles = std::move(ex);
  }
  return g;
}

void Reader::read_particles(const YamlMap& root) {
  for (const auto& item : root.at("particles").as_list(1)) c.particles.push_back(read_group(item));
}

config::Motion Reader::read_motion(const YamlNode& node) {
  config::Motion m;
  YamlMap mm(node, {"translate", "rotate"});
  if (auto t = mm.find("translate")) {
    YamlMap tm(*t, {"velocity"});
    m.velocity = tm.vec3("velocity");
  }
  if (auto r = mm.find("rotate")) {
    YamlMap rm(*r, {"axis", "center", "rpm", "rate"});
    m.rotates = true;
    m.axis = rm.at("axis").as_direction();
    m.center = rm.vec3_or("center", Vec3{});
    const std::string which = rm.exactly_one_of({"rpm", "rate"});
    const double v = rm.number(which);
    m.rate = which == "rpm" ? v * 2 * std::numbers::pi / 60.0 : v;
  }
  return m;
}

void Reader::read_walls(const YamlMap& root) {
  auto wn = root.find("walls");
  if (!wn) return;
  std::map<std::string, int> names;  // name -> line
  for (const auto& item : wn->as_list()) {
    YamlMap wm(item, {"name", "plane", "box", "cylinder", "mesh", "material", "motion"});
    config::Wall w;
    w.loc = item.loc();
    const YamlNode name = wm.at("name");
    w.name = name.as_string();
    const bool ok_start = !w.name.empty() &&
                          (std::isalpha(static_cast<unsigned char>(w.name[0])) || w.name[0] == '_');
    const bool ok_rest = std::all_of(w.name.begin(), w.name.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-';
    });
    if (!ok_start || !ok_rest)
      name.fail_expected(
          "a wall name of letters, digits, '_' and '-', starting with a letter or '_'");
    if (auto it = names.find(w.name); it != names.end())
      name.fail(
          fmt::format("duplicate wall name '{}' (first used at line {})", w.name, it->second));
    names.emplace(w.name, name.line());

    const std::string kind = wm.exactly_one_of({"plane", "box", "cylinder", "mesh"});
    if (kind == "mesh")
      wm.at("mesh").fail("mesh walls (STL) are not available yet; use plane, box or cylinder");
    if (kind == "plane") {
      YamlMap pm(wm.at("plane"), {"point", "normal"});
      w.kind = config::Wall::Kind::Plane;
      w.point = pm.vec3("point");
      w.normal = pm.at("normal").as_direction();
    } else if (kind == "box") {
      YamlMap bm(wm.at("box"), {"min", "max", "open"});
      w.kind = config::Wall::Kind::Box;
      w.min = bm.vec3("min");
      w.max = bm.vec3("max");
      for (int k = 0; k < 3; ++k)
        if (!(w.max[k] > w.min[k]))
          bm.at("max").fail_expected(
              fmt::format("every component greater than that of min {}", vec_text(w.min)));
      if (auto o = bm.find("open")) {
        for (const auto& face : o->as_list()) {
          const std::string f = face.as_choice({"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"});
          if (std::find(w.open.begin(), w.open.end(), f) != w.open.end())
            face.fail(fmt::format("face '{}' is listed twice", f));
          w.open.push_back(f);
        }
      }
    } else {
      YamlMap cm(wm.at("cylinder"), {"center", "axis", "radius", "inside"});
      w.kind = config::Wall::Kind::Cylinder;
      w.center = cm.vec3("center");
      if (auto a = cm.find("axis")) w.axis = a->as_direction();
      w.radius = cm.number("radius", Range::positive());
      w.inside = cm.boolean_or("inside", true);
    }
    const YamlNode mat = wm.at("material");
    w.material = material_ref(mat);
    wall_material_refs.emplace_back(w.material, mat.loc());
    if (auto mo = wm.find("motion")) w.motion = read_motion(*mo);
    c.walls.push_back(std::move(w));
  }
}

void Reader::read_output(const YamlMap& root) {
  auto on = root.find("output");
  if (!on) return;
  YamlMap om(*on, {"directory", "vtk", "particles_csv", "series", "checkpoint"});
  if (auto d = om.find("directory")) {
    const std::string dir = d->as_string();
    if (dir.empty()) d->fail_expected("a folder name");
    c.output.directory = dir;
  }
  auto every = [&](const YamlMap& m) {
    auto n = m.find("every");
    if (!n) return 0.0;
    const double v = n->as_number(Range::non_negative());
    if (v > 0 && v < c.time.step)
      n->fail_expected(
          fmt::format("0 (off) or an interval >= time.step ({} s)", number_text(c.time.step)));
    return v;
  };
  for (auto [key, target] :
       {std::pair{"vtk", &c.output.vtk}, std::pair{"particles_csv", &c.output.particles_csv},
        std::pair{"checkpoint", &c.output.checkpoint}}) {
    if (auto n = om.find(key)) target->every = every(YamlMap(*n, {"every"}));
  }
  if (auto s = om.find("series")) {
    YamlMap sm(*s, {"every", "quantities"});
    c.output.series.every = every(sm);
    std::vector<std::string> walls;
    for (const auto& w : c.walls) {
      walls.push_back(w.name);
      // The faces of a box report on their own too: NAME.xmin ... NAME.zmax.
      if (w.kind == config::Wall::Kind::Box)
        for (const char* face : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
          if (std::find(w.open.begin(), w.open.end(), face) == w.open.end())
            walls.push_back(w.name + "." + face);
    }
    if (auto q = sm.find("quantities")) {
      for (const auto& item : q->as_list()) {
        const std::string name = item.as_string();
        if (!is_series_quantity(name, walls)) {
          for (const char* prefix : {"wall_force.", "wall_torque."}) {
            if (name.rfind(prefix, 0) == 0) {
              std::string wall = name.substr(std::string_view(prefix).size());
              for (const char* comp : {".x", ".y", ".z"})
                if (wall.size() > 2 && wall.substr(wall.size() - 2) == comp)
                  wall.resize(wall.size() - 2);
              item.fail(fmt::format("unknown wall '{}' in '{}'; {}", wall, name,
                                    walls.empty()
                                        ? std::string("no walls are declared")
                                        : fmt::format("declared walls: {}", join(walls))));
            }
          }
          std::string hint;
          if (auto near = closest_match(name, series_quantity_names()))
            hint = fmt::format(" (did you mean '{}'?)", *near);
          item.fail(fmt::format(
              "unknown series quantity '{}'{}; accepted: {}, wall_force.WALL, wall_torque.WALL "
              "(optionally with .x, .y or .z)",
              name, hint, join(series_quantity_names())));
        }
        if (std::find(c.output.quantities.begin(), c.output.quantities.end(), name) !=
            c.output.quantities.end())
          item.fail(fmt::format("quantity '{}' is listed twice", name));
        c.output.quantities.push_back(name);
      }
    }
    if (c.output.series.every > 0 && c.output.quantities.empty()) {
      config::SourceLoc loc = s->key_loc();
      loc.key_path = s->path() + ".quantities";
      throw_input_error(
          loc, "missing required key 'quantities' (the series to write, e.g. [kinetic_energy])");
    }
  }
}

void Reader::check_pairs() const {
  std::set<std::pair<std::string, std::string>> given;
  for (const auto& ct : c.contacts) given.insert(std::minmax(ct.between[0], ct.between[1]));
  auto require = [&](const std::string& a, const std::string& b, const config::SourceLoc& where) {
    const auto key = std::minmax(a, b);
    if (given.count(key)) return;
    throw_input_error(
        where,
        fmt::format("no contacts entry for the material pair ({}, {}); add one under contacts:, "
                    "e.g. '- {{between: [{}, {}], model: hertz_mindlin, restitution: 0.5}}'",
                    key.first, key.second, key.first, key.second));
  };
  for (std::size_t i = 0; i < particle_materials.size(); ++i)
    for (std::size_t j = 0; j <= i; ++j)
      require(particle_materials[j], particle_materials[i],
              particle_material_ref.at(particle_materials[i]));
  if (particle_materials.empty()) return;
  for (const auto& [wm, loc] : wall_material_refs)
    for (const auto& pm : particle_materials) require(pm, wm, loc);
}

config::Case parse(const YamlNode& root, const fs::path& file) {
  config::Case c;
  c.file = file;
  Reader r{file.parent_path(), c, {}, {}, {}};
  YamlMap rm(root, {"name", "dimension", "time", "domain", "gravity", "integrator", "materials",
                    "contacts", "particles", "walls", "output", "neighbor"});
  if (auto n = rm.find("name")) {
    c.name = n->as_string();
    if (c.name.empty()) n->fail_expected("a case name");
  } else {
    c.name = fs::absolute(file).parent_path().filename().string();
    if (c.name.empty()) c.name = file.stem().string();
  }
  if (auto d = rm.find("dimension")) {
    const auto dim = d->as_integer();
    if (dim == 2) d->fail("2D runs are not available yet; use dimension: 3");
    if (dim != 3) d->fail_expected("3 (or 2, once 2D runs are available)");
    c.dimension = 3;
  }
  r.read_time(rm);
  r.read_domain(rm);
  c.gravity = rm.vec3_or("gravity", c.gravity);
  if (auto i = rm.find("integrator")) {
    const std::string s = i->as_string();
    if (s == "gear") i->fail("integrator 'gear' is not available yet; use velocity_verlet");
    c.integrator = i->as_choice({"velocity_verlet"});
  }
  r.read_materials(rm);
  r.read_contacts(rm);
  r.read_particles(rm);
  r.read_walls(rm);
  r.read_output(rm);
  if (auto n = rm.find("neighbor")) {
    YamlMap nm(*n, {"skin"});
    c.neighbor.skin = nm.optional_number("skin", Range::positive());
  }
  r.check_pairs();
  return c;
}

}  // namespace

const std::vector<std::string>& series_quantity_names() {
  static const std::vector<std::string> names{"kinetic_energy",
                                              "translational_kinetic_energy",
                                              "rotational_kinetic_energy",
                                              "potential_energy",
                                              "elastic_energy",
                                              "total_energy",
                                              "max_z",
                                              "mean_z",
                                              "contact_count",
                                              "coordination_number"};
  return names;
}

bool is_series_quantity(std::string_view quantity, const std::vector<std::string>& wall_names) {
  const auto& names = series_quantity_names();
  if (std::find(names.begin(), names.end(), quantity) != names.end()) return true;
  for (std::string_view prefix : {"wall_force.", "wall_torque."}) {
    if (quantity.substr(0, prefix.size()) != prefix) continue;
    std::string_view wall = quantity.substr(prefix.size());
    if (std::find(wall_names.begin(), wall_names.end(), wall) != wall_names.end()) return true;
    if (wall.size() > 2 && wall[wall.size() - 2] == '.' &&
        (wall.back() == 'x' || wall.back() == 'y' || wall.back() == 'z')) {
      wall.remove_suffix(2);
      if (std::find(wall_names.begin(), wall_names.end(), wall) != wall_names.end()) return true;
    }
  }
  return false;
}

config::Case load_case(const fs::path& file) {
  return parse(YamlNode::parse_file(file), file);
}

config::Case load_case_text(const std::string& yaml_text, const fs::path& file) {
  return parse(YamlNode::parse_text(yaml_text, file.string()), file);
}

}  // namespace gf::input
