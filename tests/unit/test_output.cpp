// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of io output: HDF5 checkpoints (bit-exact), CSV, VTK .vtp/.pvd, atomic writes.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <ranges>
#include <sstream>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/quaternion.hpp"
#include "io/csv/csv.hpp"
#include "io/input/parse_case.hpp"
#include "io/restart/h5.hpp"
#include "io/vtk/vtk.hpp"
#include "simulation/output_clock.hpp"
#include "simulation/simulation.hpp"
#include "temp_dir.hpp"
#include "vtk_reader.hpp"

using namespace gf;
namespace fs = std::filesystem;

namespace {

using test::TempDir;

std::string slurp(const fs::path& p) {
  return read_text_file(p);
}

/// A store with random values in every column, special doubles included, and custom fields.
ParticleStore random_store(std::size_t n, std::uint64_t seed) {
  ParticleStore s;
  s.add_field("temperature", FieldType::Real, "K", kRestart | kOutput);
  s.add_field("orientation_axis", FieldType::Vec3, "1", kRestart | kOutput);
  s.add_field("n_contacts", FieldType::Int32, "1", kRestart);
  s.add_field("scratch", FieldType::Real, "1", kOutput);  // not in checkpoints
  s.resize(n);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  const double specials[] = {-0.0,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::max(),
                             -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN(),
                             1.0 / 3.0};
  auto value = [&](std::size_t i) {
    return i < std::size(specials) ? specials[i]
                                   : u(rng) * std::pow(10.0, static_cast<int>(rng() % 40) - 20);
  };
  for (std::size_t f = 0; f < s.fields().size(); ++f) {
    std::visit(
        [&](auto& v) {
          using T = typename std::decay_t<decltype(v)>::value_type;
          for (std::size_t i = 0; i < n; ++i) {
            if constexpr (std::is_same_v<T, double>)
              v[i] = value(i);
            else if constexpr (std::is_same_v<T, Vec3>)
              v[i] = {value(i), u(rng), value(n - 1 - i)};
            else
              v[i] = static_cast<T>(rng());
          }
        },
        s.column(static_cast<int>(f)));
  }
  for (std::size_t i = 0; i < n; ++i) s.id()[i] = static_cast<std::int64_t>(1000 + 7 * i);
  return s;
}

/// Byte-wise equality of two columns.
bool same_bits(const Column& a, const Column& b) {
  if (a.index() != b.index()) return false;
  return std::visit(
      [&](const auto& va) {
        const auto& vb = std::get<std::decay_t<decltype(va)>>(b);
        return va.size() == vb.size() &&
               (va.empty() || std::memcmp(va.data(), vb.data(), va.size() * sizeof(va[0])) == 0);
      },
      a);
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  return "<no IoError>";
}

}  // namespace

// ---- HDF5 -----------------------------------------------------------------------------------

TEST(H5, ParticleStoreRoundTripIsBitExact) {
  TempDir dir;
  const ParticleStore saved = random_store(257, 42);
  io::write_checkpoint_atomically(dir / "ck.h5",
                                  [&](io::h5::File& f) { io::save_particles(f, saved); });

  ParticleStore loaded;
  loaded.add_field("temperature", FieldType::Real, "K", kRestart | kOutput);
  loaded.add_field("orientation_axis", FieldType::Vec3, "1", kRestart | kOutput);
  loaded.add_field("n_contacts", FieldType::Int32, "1", kRestart);
  const int scratch = loaded.add_field("scratch", FieldType::Real, "1", kOutput);
  loaded.resize(3);
  loaded.get<double>(scratch)[0] = 5.0;
  auto f = io::h5::File::open_read(dir / "ck.h5");
  io::load_particles(f, loaded);

  ASSERT_EQ(loaded.size(), saved.size());
  for (std::size_t k = 0; k < saved.fields().size(); ++k) {
    if (!(saved.fields()[k].flags & kRestart)) continue;
    EXPECT_TRUE(same_bits(saved.column(static_cast<int>(k)), loaded.column(static_cast<int>(k))))
        << saved.fields()[k].name;
  }
  for (double x : loaded.get<double>(scratch)) EXPECT_EQ(x, 0.0);  // not restarted: zero
  EXPECT_EQ(f.read_string_attribute("particles/radius", "unit"), "m");
  EXPECT_EQ(f.read_string_attribute("particles/temperature", "unit"), "K");
  EXPECT_EQ(f.read_string_attribute("particles/position", "type"), "vec3");
  EXPECT_EQ(f.read_int_attribute("particles", "count"), 257);
  EXPECT_FALSE(f.exists("particles/scratch"));
}

TEST(H5, EmptyStoreRoundTrip) {
  TempDir dir;
  ParticleStore plain;
  {
    auto f = io::h5::File::create(dir / "e.h5");
    io::save_particles(f, plain, "state/particles");
    f.close();
  }
  ParticleStore target;
  target.resize(10);
  auto f = io::h5::File::open_read(dir / "e.h5");
  io::load_particles(f, target, "state/particles");
  EXPECT_EQ(target.size(), 0u);
}

TEST(H5, DatasetsAttributesAndGroups) {
  TempDir dir;
  const std::vector<double> d = {1.5, -0.0, 1e-310, std::numeric_limits<double>::infinity()};
  const std::vector<std::int64_t> i64 = {std::numeric_limits<std::int64_t>::min(), 0, 42};
  const std::vector<std::int32_t> i32 = {-7, std::numeric_limits<std::int32_t>::max()};
  const std::vector<std::uint8_t> u8 = {0, 1, 255};
  const std::vector<Vec3> v3 = {{1, 2, 3}, {4, 5, 6}};
  {
    auto f = io::h5::File::create(dir / "a.h5");
    f.write("d", std::span<const double>(d));
    f.write("contacts/pairs/i64", std::span<const std::int64_t>(i64));  // creates the groups
    f.write("contacts/i32", std::span<const std::int32_t>(i32));
    f.write("flags", std::span<const std::uint8_t>(u8));
    f.write("contacts/pairs/v3", std::span<const Vec3>(v3));
    f.write("d", std::span<const double>(d).first(2));  // replaces
    f.create_group("empty/inner");
    f.create_group("empty/inner");  // existing: fine
    f.set_attribute("", "program", "grainflow");
    f.set_attribute("/", "time", 0.125);
    f.set_attribute("contacts", "count", std::int64_t{3});
    f.set_attribute("contacts/pairs/v3", "unit", std::string("m"));
    f.set_attribute("contacts", "step", 17);
    f.set_attribute("contacts", "step", 18);  // replaces
    f.set_attribute("empty", "note", std::string());
    f.close();
    f.close();  // idempotent
  }
  auto f = io::h5::File::open_read(dir / "a.h5");
  EXPECT_TRUE(f.exists("contacts/pairs"));
  EXPECT_TRUE(f.exists("/contacts/pairs/v3"));
  EXPECT_TRUE(f.exists(""));
  EXPECT_FALSE(f.exists("contacts/nothing/deeper"));
  EXPECT_FALSE(f.exists("d/below_a_dataset"));
  EXPECT_TRUE(f.is_group("empty/inner"));
  EXPECT_FALSE(f.is_group("d"));
  EXPECT_EQ(f.list("contacts"), (std::vector<std::string>{"i32", "pairs"}));
  EXPECT_EQ(f.read_double("d"), std::vector<double>(d.begin(), d.begin() + 2));
  EXPECT_EQ(f.read_int64("contacts/pairs/i64"), i64);
  EXPECT_EQ(f.read_int32("contacts/i32"), i32);
  EXPECT_EQ(f.read_uint8("flags"), u8);
  EXPECT_EQ(f.read_vec3("contacts/pairs/v3"), v3);
  EXPECT_EQ(f.read_int64("flags"), (std::vector<std::int64_t>{0, 1, 255}));  // widening is fine
  const auto info = f.info("contacts/pairs/v3");
  EXPECT_EQ(info.shape, (std::vector<std::uint64_t>{2, 3}));
  EXPECT_EQ(info.type_class, io::h5::DatasetInfo::Class::Float);
  EXPECT_EQ(f.read_string_attribute("/", "program"), "grainflow");
  EXPECT_EQ(f.read_double_attribute("", "time"), 0.125);
  EXPECT_EQ(f.read_int_attribute("contacts", "count"), 3);
  EXPECT_EQ(f.read_int_attribute("contacts", "step"), 18);
  EXPECT_EQ(f.read_string_attribute("contacts/pairs/v3", "unit"), "m");
  EXPECT_EQ(f.read_string_attribute("empty", "note"), "");
  EXPECT_TRUE(f.has_attribute("contacts", "count"));
  EXPECT_FALSE(f.has_attribute("contacts", "nope"));
  EXPECT_FALSE(f.has_attribute("missing_group", "nope"));
}

TEST(H5, ErrorsNameTheFileAndTheDataset) {
  TempDir dir;
  const std::string missing = error_of([&] { io::h5::File::open_read(dir / "nope.h5"); });
  EXPECT_NE(missing.find("nope.h5"), std::string::npos) << missing;

  std::ofstream(dir / "text.h5") << "not hdf5\n";
  const std::string not_h5 = error_of([&] { io::h5::File::open_read(dir / "text.h5"); });
  EXPECT_NE(not_h5.find("text.h5"), std::string::npos) << not_h5;

  {
    auto f = io::h5::File::create(dir / "a.h5");
    f.write("grp/x", std::span<const double>(std::vector<double>{1, 2}));
    f.write("grp/i", std::span<const std::int64_t>(std::vector<std::int64_t>{1, 2}));
  }
  auto f = io::h5::File::open_read(dir / "a.h5");
  std::string e = error_of([&] { f.read_double("grp/y"); });
  EXPECT_NE(e.find("a.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("grp/y"), std::string::npos) << e;
  e = error_of([&] { f.read_int64("grp/x"); });  // float read as integer
  EXPECT_NE(e.find("grp/x"), std::string::npos) << e;
  e = error_of([&] { f.read_vec3("grp/x"); });  // wrong shape
  EXPECT_NE(e.find("shape"), std::string::npos) << e;
  e = error_of([&] { f.read_int32("grp/i"); });  // narrowing
  EXPECT_NE(e.find("grp/i"), std::string::npos) << e;
  std::vector<double> three(3);
  e = error_of([&] { f.read("grp/x", std::span<double>(three)); });
  EXPECT_NE(e.find("rows"), std::string::npos) << e;
  e = error_of([&] { f.write("grp/z", std::span<const double>(three)); });  // read-only
  EXPECT_NE(e.find("grp/z"), std::string::npos) << e;
  e = error_of([&] { f.read_string_attribute("grp", "missing"); });
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
  f.close();
  e = error_of([&] { f.exists("grp"); });
  EXPECT_NE(e.find("closed"), std::string::npos) << e;
}

TEST(H5, MissingOrMistypedFieldIsAnError) {
  TempDir dir;
  ParticleStore saved = random_store(5, 3);
  saved.add_field("old_field", FieldType::Int64, "1", kRestart);  // unknown to the loader: ignored
  saved.add_field("clash", FieldType::Int64, "1", kRestart);
  {
    auto f = io::h5::File::create(dir / "ck.h5");
    io::save_particles(f, saved);
  }
  auto f = io::h5::File::open_read(dir / "ck.h5");

  {  // a restart field the file lacks
    ParticleStore s = random_store(0, 1);
    s.add_field("new_field", FieldType::Real, "1", kRestart);
    s.resize(2);
    const std::string e = error_of([&] { io::load_particles(f, s); });
    EXPECT_NE(e.find("new_field"), std::string::npos) << e;
    EXPECT_NE(e.find("missing"), std::string::npos) << e;
    EXPECT_EQ(s.size(), 2u);  // untouched
  }
  {  // a restart field of another type
    ParticleStore s = random_store(0, 1);
    s.add_field("clash", FieldType::Vec3, "1", kRestart);
    const std::string e = error_of([&] { io::load_particles(f, s); });
    EXPECT_NE(e.find("clash"), std::string::npos) << e;
  }
  {  // an extra field in the file: ignored if it is not a store field ...
    ParticleStore s = random_store(0, 1);
    s.add_field("clash", FieldType::Int64, "1", kRestart);
    EXPECT_NO_THROW(io::load_particles(f, s));
    EXPECT_EQ(s.size(), 5u);
  }
  {  // ... and an error if a non-restart store field of that name has another type
    ParticleStore s = random_store(0, 1);
    s.add_field("clash", FieldType::Int64, "1", kRestart);
    s.add_field("old_field", FieldType::Real, "1", kOutput);
    const std::string e = error_of([&] { io::load_particles(f, s); });
    EXPECT_NE(e.find("old_field"), std::string::npos) << e;
  }
  {  // no such group
    ParticleStore s;
    const std::string e = error_of([&] { io::load_particles(f, s, "elsewhere"); });
    EXPECT_NE(e.find("elsewhere"), std::string::npos) << e;
  }
}

TEST(OutputAtomic, ThrowingCheckpointLeavesNothingBehind) {
  TempDir dir;
  const ParticleStore s = random_store(10, 7);
  EXPECT_THROW(io::write_checkpoint_atomically(dir / "new.h5",
                                               [&](io::h5::File& f) {
                                                 io::save_particles(f, s);
                                                 throw IoError("disk full (simulated)");
                                               }),
               IoError);
  EXPECT_TRUE(dir.entries().empty());

  io::write_checkpoint_atomically(dir / "ck.h5",
                                  [&](io::h5::File& f) { io::save_particles(f, s); });
  const std::string before = slurp(dir / "ck.h5");
  EXPECT_THROW(io::write_checkpoint_atomically(dir / "ck.h5",
                                               [&](io::h5::File& f) {
                                                 f.set_attribute("", "partial", 1);
                                                 throw std::runtime_error("interrupted");
                                               }),
               std::runtime_error);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"ck.h5"});
  EXPECT_EQ(slurp(dir / "ck.h5"), before);
}

TEST(OutputAtomic, FailedWritersLeaveExistingFilesUntouched) {
  TempDir dir;
  std::ofstream(dir / "walls.vtp") << "old";
  std::ofstream(dir / "p.csv") << "old";
  const SurfaceMesh bad{"bad", {{0, 0, 0}}, {{0, 1, 2}}};  // vertices out of range
  const Vec3 force{};
  EXPECT_THROW(io::write_surfaces_vtp(dir / "walls.vtp", std::span(&bad, 1), std::span(&force, 1)),
               Error);
  ParticleStore s = random_store(3, 1);
  s.add_field("a,b", FieldType::Real, "1", kOutput);  // cannot be a CSV column
  EXPECT_THROW(io::write_particles_csv(dir / "p.csv", s), Error);
  EXPECT_EQ(slurp(dir / "walls.vtp"), "old");
  EXPECT_EQ(slurp(dir / "p.csv"), "old");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"p.csv", "walls.vtp"}));
  // A folder that does not exist: IoError, nothing created.
  EXPECT_THROW(io::write_particles_vtp(dir / "no_such_dir" / "p.vtp", s), IoError);
  EXPECT_FALSE(fs::exists(dir / "no_such_dir"));
}

// ---- CSV ------------------------------------------------------------------------------------

TEST(Csv, ParticleHeaderAndValuesRoundTrip) {
  TempDir dir;
  ParticleStore s;
  s.add_sphere(7, 1, 0.005, 2500, {0.1, 0.2, 1.0 / 3.0}, {-1e-300, 0, 2.5}, {0, 0, 1});
  s.add_sphere(9, 0, 0.0075, 2500, {1, 2, 3});
  s.f()[1] = {1e20, -0.0, 123456789.123};
  EXPECT_EQ(fmt::format("{}", fmt::join(io::particle_csv_columns(s), ",")),
            "id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz");
  const int extra = s.add_field("spin_axis", FieldType::Vec3, "1", kOutput);
  s.add_field("hidden", FieldType::Real, "1", kRestart);
  s.get<Vec3>(extra)[0] = {0.6, 0.8, 0};

  io::write_particles_csv(dir / "p.csv", s);
  std::istringstream in(slurp(dir / "p.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(
      line,
      "id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,spin_axis_x,spin_axis_y,spin_axis_z");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[0].size(), 18u);
  EXPECT_EQ(rows[0][0], "7");
  EXPECT_EQ(rows[0][1], "1");
  EXPECT_EQ(rows[0][2], "0.005");
  EXPECT_EQ(std::strtod(rows[0][5].c_str(), nullptr), 1.0 / 3.0);  // shortest round-trip
  EXPECT_EQ(std::strtod(rows[0][6].c_str(), nullptr), -1e-300);
  EXPECT_EQ(rows[0][15], "0.6");
  EXPECT_EQ(rows[1][0], "9");
  EXPECT_EQ(rows[1][12], "1e+20");
  EXPECT_EQ(rows[1][13], "-0");
  EXPECT_EQ(std::strtod(rows[1][14].c_str(), nullptr), 123456789.123);
}

TEST(Csv, SeriesAppendsAndFlushes) {
  TempDir dir;
  {
    io::SeriesCsv csv(dir / "series.csv", {"kinetic_energy", "wall_force.floor"});
    EXPECT_EQ(slurp(dir / "series.csv"), "time,kinetic_energy,wall_force.floor\n");  // header now
    csv.append(0.0, {1.0, 0.1});
    const std::vector<double> row = {2.0 / 3.0, -4e-8};
    csv.append(1e-3, row);
    csv.flush();
    EXPECT_EQ(slurp(dir / "series.csv"),
              "time,kinetic_energy,wall_force.floor\n0,1,0.1\n0.001,0.6666666666666666,-4e-08\n");
    csv.append(2e-3, {0, 0});
    EXPECT_THROW(csv.append(3e-3, {1.0}), Error);
  }  // destruction flushes
  EXPECT_EQ(slurp(dir / "series.csv"),
            "time,kinetic_energy,wall_force.floor\n0,1,0.1\n0.001,0.6666666666666666,-4e-08\n"
            "0.002,0,0\n");
  EXPECT_THROW(io::SeriesCsv(dir / "missing_dir" / "s.csv", {"a"}), IoError);
}

// Continuing a series (--append): rows up to the continuation time are kept; a series written
// by an earlier build with fewer columns at the end gets "nan" in the new ones (its kept rows
// and its file); any other change of columns is an input error, leaving the file as it was.
TEST(Csv, SeriesContinuesAnEarlierBuildsColumns) {
  TempDir dir;
  const std::string old_text = "time,a,b\n0,1,2\n1,3,4\n2,5,6\n";
  std::ofstream(dir / "s.csv") << old_text;
  for (const std::vector<std::string>& cols :
       {std::vector<std::string>{"a", "c"}, std::vector<std::string>{"a"},
        std::vector<std::string>{"b", "a", "c"}, std::vector<std::string>{"ab", "c"}}) {
    EXPECT_THROW(io::SeriesCsv(dir / "s.csv", cols, io::SeriesContinuation{1.5, true}), InputError)
        << cols.size();
    EXPECT_EQ(slurp(dir / "s.csv"), old_text);
  }
  {
    io::SeriesCsv csv(dir / "s.csv", {"a", "b", "c", "d"}, io::SeriesContinuation{1.0, true});
    ASSERT_EQ(csv.kept_rows().size(), 2u);
    EXPECT_EQ(csv.kept_rows()[1][2], 4.0);
    EXPECT_TRUE(std::isnan(csv.kept_rows()[1][3]));
    EXPECT_TRUE(std::isnan(csv.kept_rows()[1][4]));
    csv.append(1.5, {7, 8, 9, 10});
  }
  EXPECT_EQ(slurp(dir / "s.csv"), "time,a,b,c,d\n0,1,2,nan,nan\n1,3,4,nan,nan\n1.5,7,8,9,10\n");
}

// ---- VTK ------------------------------------------------------------------------------------

namespace {

using Vtp = test::VtkFile;

std::vector<double> flat(std::span<const Vec3> v) {
  std::vector<double> out;
  for (const auto& p : v) out.insert(out.end(), {p.x, p.y, p.z});
  return out;
}

}  // namespace

TEST(Vtk, ParticlesFileStructureAndData) {
  TempDir dir;
  ParticleStore s = random_store(33, 11);
  io::write_particles_vtp(dir / "p.vtp", s);
  const Vtp vtp(dir / "p.vtp");

  EXPECT_NE(vtp.header.find("type=\"PolyData\""), std::string::npos);
  EXPECT_NE(vtp.header.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(vtp.header.find("byte_order=\"LittleEndian\""), std::string::npos);
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "33");
  EXPECT_EQ(vtp.piece("NumberOfVerts"), "33");
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());

  // Exactly the kOutput fields except position, plus speed; position as the points.
  std::vector<std::string> keys;
  for (const auto& [k, a] : vtp.arrays) keys.push_back(k);
  EXPECT_EQ(keys,
            (std::vector<std::string>{
                "PointData/angular_velocity", "PointData/force", "PointData/id",
                "PointData/material", "PointData/orientation_axis", "PointData/radius",
                "PointData/scratch", "PointData/speed", "PointData/temperature",
                "PointData/velocity", "Points/position", "Verts/connectivity", "Verts/offsets"}));

  const std::size_t n = s.size();
  auto same_doubles = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * 8) == 0);
  };
  EXPECT_TRUE(same_doubles(vtp.get<double>("Points/position", "Float64", 3), flat({s.x(), n})));
  EXPECT_TRUE(same_doubles(vtp.get<double>("PointData/velocity", "Float64", 3), flat({s.v(), n})));
  EXPECT_TRUE(same_doubles(vtp.get<double>("PointData/force", "Float64", 3), flat({s.f(), n})));
  EXPECT_TRUE(same_doubles(vtp.get<double>("PointData/radius", "Float64", 1),
                           std::vector<double>(s.radius(), s.radius() + n)));
  EXPECT_EQ(vtp.get<std::int64_t>("PointData/id", "Int64", 1),
            std::vector<std::int64_t>(s.id(), s.id() + n));
  EXPECT_EQ(vtp.get<std::int32_t>("PointData/material", "Int32", 1),
            std::vector<std::int32_t>(s.material(), s.material() + n));
  const auto speed = vtp.get<double>("PointData/speed", "Float64", 1);
  ASSERT_EQ(speed.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    const double expected = norm(s.v()[i]);
    if (std::isnan(expected))
      EXPECT_TRUE(std::isnan(speed[i]));
    else
      EXPECT_EQ(speed[i], expected);
  }
  const auto conn = vtp.get<std::int64_t>("Verts/connectivity", "Int64", 1);
  const auto offs = vtp.get<std::int64_t>("Verts/offsets", "Int64", 1);
  ASSERT_EQ(conn.size(), n);
  ASSERT_EQ(offs.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(conn[i], static_cast<std::int64_t>(i));
    EXPECT_EQ(offs[i], static_cast<std::int64_t>(i + 1));
  }
}

TEST(Vtk, EmptyParticleStoreIsValid) {
  TempDir dir;
  io::write_particles_vtp(dir / "p.vtp", ParticleStore{});
  const Vtp vtp(dir / "p.vtp");
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "0");
  EXPECT_TRUE(vtp.get<double>("Points/position", "Float64", 3).empty());
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());
}

TEST(Vtk, SurfacesCarryWallIdAndForce) {
  TempDir dir;
  const std::vector<SurfaceMesh> meshes = {
      {"floor", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}},
      {"lid", {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}, {{0, 1, 2}}}};
  const std::vector<Vec3> forces = {{0, 0, 9.81}, {1.5, -2, 0}};
  io::write_surfaces_vtp(dir / "walls.vtp", meshes, forces);
  const Vtp vtp(dir / "walls.vtp");
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "7");
  EXPECT_EQ(vtp.piece("NumberOfPolys"), "3");
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());
  EXPECT_EQ(vtp.get<double>("Points/position", "Float64", 3),
            (std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1}));
  EXPECT_EQ(vtp.get<std::int64_t>("Polys/connectivity", "Int64", 1),
            (std::vector<std::int64_t>{0, 1, 2, 0, 2, 3, 4, 5, 6}));
  EXPECT_EQ(vtp.get<std::int64_t>("Polys/offsets", "Int64", 1),
            (std::vector<std::int64_t>{3, 6, 9}));
  EXPECT_EQ(vtp.get<std::int32_t>("CellData/wall_id", "Int32", 1),
            (std::vector<std::int32_t>{0, 0, 1}));
  EXPECT_EQ(vtp.get<double>("CellData/wall_force", "Float64", 3),
            (std::vector<double>{0, 0, 9.81, 0, 0, 9.81, 1.5, -2, 0}));

  EXPECT_THROW(io::write_surfaces_vtp(dir / "w2.vtp", meshes, std::span(forces).first(1)), Error);
}

TEST(Vtk, EmptySurfaceListIsValid) {
  TempDir dir;
  io::write_surfaces_vtp(dir / "walls.vtp", {}, {});
  const Vtp vtp(dir / "walls.vtp");
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "0");
  EXPECT_EQ(vtp.piece("NumberOfPolys"), "0");
  EXPECT_TRUE(vtp.get<std::int32_t>("CellData/wall_id", "Int32", 1).empty());
  EXPECT_TRUE(vtp.get<std::int64_t>("Polys/offsets", "Int64", 1).empty());
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());
}

TEST(Vtk, PvdSeriesIsRewrittenOnEveryAdd) {
  TempDir dir;
  io::PvdSeries pvd(dir / "particles.pvd");
  EXPECT_FALSE(fs::exists(dir / "particles.pvd"));
  pvd.add(0.0, "particles_000000.vtp");
  const std::string head =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  const std::string foot = "  </Collection>\n</VTKFile>\n";
  EXPECT_EQ(
      slurp(dir / "particles.pvd"),
      head + "    <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"particles_000000.vtp\"/>\n" +
          foot);
  pvd.add(0.1, "vtk/particles_000001.vtp");
  pvd.add(0.1, "a&b \"c\".vtp", 1);
  EXPECT_EQ(pvd.size(), 3u);
  EXPECT_EQ(
      slurp(dir / "particles.pvd"),
      head + "    <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"particles_000000.vtp\"/>\n" +
          "    <DataSet timestep=\"0.1\" group=\"\" part=\"0\" "
          "file=\"vtk/particles_000001.vtp\"/>\n" +
          "    <DataSet timestep=\"0.1\" group=\"\" part=\"1\" file=\"a&amp;b "
          "&quot;c&quot;.vtp\"/>\n" +
          foot);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"particles.pvd"});  // no temporary left

  io::PvdSeries broken(dir / "missing_dir" / "x.pvd");
  EXPECT_THROW(broken.add(0.0, "x.vtp"), IoError);
  EXPECT_EQ(broken.size(), 0u);
}

// The CFD-DEM fluid's cell fields as ImageData: the extent and spacing of the grid, and the
// fluid fraction, pressure and cell-centre velocity read back bit for bit (binary blocks), after
// a few fluid steps of the fluidized bed (the fluid is moving and eps varies).
TEST(Vtk, FluidVtiCarriesTheCellFieldsBitExactly) {
  const auto cfg =
      input::load_case(std::string(GF_SOURCE_DIR) + "/cases/cfd_dem/fluidized_bed/case.yaml");
  Simulation sim(cfg);
  for (int s = 0; s < 100; ++s) sim.step();
  const CfdDemCoupling& cfd = *sim.cfd_dem();
  const auto& f = cfd.fluid();
  const auto& g = f.grid();
  test::TempDir dir;
  write_atomically(dir / "f.vti", [&](std::ostream& o) { cfd.write_vti(o); });
  const Vtp v(dir / "f.vti");
  EXPECT_EQ(v.piece("Extent"), fmt::format("0 {} 0 {} 0 {}", g.n[0], g.n[1], g.n[2]));
  EXPECT_NE(v.header.find("<VTKFile type=\"ImageData\""), std::string::npos);
  EXPECT_EQ(v.blocks_size(), v.appended.size());
  const auto eps = v.get<double>("CellData/fluid_fraction", "Float64", 1);
  const auto p = v.get<double>("CellData/pressure", "Float64", 1);
  const auto u = v.get<double>("CellData/velocity", "Float64", 3);
  ASSERT_EQ(eps.size(), static_cast<std::size_t>(g.cell_count()));
  EXPECT_EQ(eps, std::vector<double>(f.fluid_fraction().begin(), f.fluid_fraction().end()));
  EXPECT_EQ(p, std::vector<double>(f.pressure().begin(), f.pressure().end()));
  std::vector<Vec3> uc(static_cast<std::size_t>(g.cell_count()));
  f.cell_velocities(uc);
  EXPECT_EQ(u, flat(uc));
  EXPECT_LT(*std::min_element(eps.begin(), eps.end()), 0.99);  // grains are in the grid
  double umax = 0.0;
  for (double x : u) umax = std::max(umax, std::abs(x));
  EXPECT_GT(umax, 0.1);
}

// ---- Shapes: glyph arrays, polygon cells, CSV columns ---------------------------------------

namespace {

constexpr double kPi = std::numbers::pi;

/// A store with every shape. Keep in step with SHAPE_SAMPLE in tests/python/test_vtk_shapes.py,
/// which checks the files written from it by OutputSample.WritesShapeSampleForPythonReadback.
///   id 100 sphere          r 0.004, identity orientation
///   id 101 spherocylinder  r_cap 0.002, half_length 0.006, 90 deg about x: axis (0, -1, 0)
///   id 102 spherocylinder  r_cap 0.001, half_length 0.004, 30 deg about y then 40 deg about z
///   id 103 polygon 0       square of side 0.01, 30 deg about z
///   id 104 disk            r 0.006, 90 deg about z: axis (0, 1, 0)
///   id 105 polygon 1       triangle, -45 deg about z
ParticleStore shape_store() {
  ParticleStore s;
  s.enable_shapes();
  auto& table = s.polygons();
  PolygonShape square;
  square.body.n = 4;
  square.body.v[0] = {-0.005, -0.005};
  square.body.v[1] = {0.005, -0.005};
  square.body.v[2] = {0.005, 0.005};
  square.body.v[3] = {-0.005, 0.005};
  square.area = 1e-4;
  square.circumradius = 0.005 * std::numbers::sqrt2;
  square.equivalent_radius = std::sqrt(1e-4 / kPi);
  table.push_back(square);
  PolygonShape triangle;
  triangle.body.n = 3;
  triangle.body.v[0] = {0.006, 0};
  triangle.body.v[1] = {-0.003, 0.0052};
  triangle.body.v[2] = {-0.003, -0.0052};
  triangle.area = 0.5 * 0.009 * 0.0104;
  triangle.circumradius = 0.006;
  triangle.equivalent_radius = std::sqrt(triangle.area / kPi);
  table.push_back(triangle);

  const Vec3 ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};
  auto add = [&](std::int64_t id, int material, ShapeCode shape, double radius, double half_length,
                 const Quat& q, int polygon, const Vec3& x, const Vec3& v, const Vec3& w) {
    const std::size_t i = s.add_sphere(id, material, radius, 2500, x, v, w);
    s.shape()[i] = static_cast<std::int32_t>(shape);
    s.half_length()[i] = half_length;
    s.orientation()[i] = q;
    s.polygon()[i] = polygon;
  };
  add(100, 0, ShapeCode::Sphere, 0.004, 0, Quat{}, -1, {0, 0, 0.01}, {0, 0, -1}, {});
  add(101, 1, ShapeCode::Spherocylinder, 0.008, 0.006, quat_from_axis_angle(ex, kPi / 2), -1,
      {0.02, 0, 0.01}, {1, 0, 0}, {0, 0, 2});
  add(102, 1, ShapeCode::Spherocylinder, 0.005, 0.004,
      quat_from_axis_angle(ez, 40 * kPi / 180) * quat_from_axis_angle(ey, 30 * kPi / 180), -1,
      {0.04, 0.01, 0.02}, {}, {0.5, 0, 0});
  add(103, 2, ShapeCode::Polygon, square.circumradius, 0, quat_from_axis_angle(ez, kPi / 6), 0,
      {0.1, 0.05, 0}, {0.5, -0.5, 0}, {0, 0, -3});
  add(104, 2, ShapeCode::Disk, 0.006, 0, quat_from_axis_angle(ez, kPi / 2), -1, {0.2, 0, 0},
      {0, 0.25, 0}, {0, 0, 1});
  add(105, 3, ShapeCode::Polygon, triangle.circumradius, 0, quat_from_axis_angle(ez, -kPi / 4), 1,
      {0.15, 0.02, 0}, {-0.1, 0, 0}, {0, 0, 0.5});
  return s;
}

std::vector<std::string> split(const std::string& line, char sep = ',') {
  std::vector<std::string> cells;
  std::stringstream ls(line);
  for (std::string c; std::getline(ls, c, sep);) cells.push_back(c);
  return cells;
}

}  // namespace

TEST(OutputShapes, AxisIsTheWorldImageOfTheBodyAxis) {
  const Quat about_x = quat_from_axis_angle({1, 0, 0}, kPi / 2);
  const Vec3 a = io::shape_axis(static_cast<std::int32_t>(ShapeCode::Spherocylinder), about_x);
  EXPECT_NEAR(a.x, 0, 1e-15);
  EXPECT_NEAR(a.y, -1, 1e-15);
  EXPECT_NEAR(a.z, 0, 1e-15);
  // Spheres: body e_z too; disks and polygons: body e_x (the plane normal would not show the
  // rotation).
  const Quat about_z = quat_from_axis_angle({0, 0, 1}, kPi / 6);
  const Vec3 s = io::shape_axis(static_cast<std::int32_t>(ShapeCode::Sphere), about_z);
  EXPECT_NEAR(s.z, 1, 1e-15);
  for (ShapeCode c : {ShapeCode::Disk, ShapeCode::Polygon}) {
    const Vec3 p = io::shape_axis(static_cast<std::int32_t>(c), about_z);
    EXPECT_NEAR(p.x, std::cos(kPi / 6), 1e-15);
    EXPECT_NEAR(p.y, std::sin(kPi / 6), 1e-15);
    EXPECT_NEAR(p.z, 0, 1e-15);
  }
}

TEST(OutputShapes, ParticlesVtpCarriesOrientationAndGlyphArrays) {
  TempDir dir;
  const ParticleStore s = shape_store();
  const std::size_t n = s.size();
  io::write_particles_vtp(dir / "p.vtp", s);
  const Vtp vtp(dir / "p.vtp");
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "6");
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());

  std::vector<std::string> keys;
  for (const auto& [k, a] : vtp.arrays) keys.push_back(k);
  EXPECT_EQ(keys,
            (std::vector<std::string>{
                "PointData/angular_velocity", "PointData/axis", "PointData/cap_offset",
                "PointData/cap_radius", "PointData/cylinder_scale", "PointData/force",
                "PointData/half_length", "PointData/id", "PointData/length", "PointData/material",
                "PointData/orientation", "PointData/polygon", "PointData/radius", "PointData/shape",
                "PointData/speed", "PointData/velocity", "Points/position", "Verts/connectivity",
                "Verts/offsets"}));

  // The quaternion: 4 x Float64, w first, bit for bit.
  const auto q = vtp.get<double>("PointData/orientation", "Float64", 4);
  ASSERT_EQ(q.size(), 4 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Quat& e = s.orientation()[i];
    EXPECT_EQ(q[4 * i + 0], e.w) << i;
    EXPECT_EQ(q[4 * i + 1], e.x) << i;
    EXPECT_EQ(q[4 * i + 2], e.y) << i;
    EXPECT_EQ(q[4 * i + 3], e.z) << i;
  }
  EXPECT_EQ(vtp.get<std::int32_t>("PointData/shape", "Int32", 1),
            (std::vector<std::int32_t>{0, 1, 1, 3, 2, 3}));
  EXPECT_EQ(vtp.get<std::int32_t>("PointData/polygon", "Int32", 1),
            (std::vector<std::int32_t>{-1, -1, -1, 0, -1, 1}));
  EXPECT_EQ(vtp.get<double>("PointData/half_length", "Float64", 1),
            (std::vector<double>{0, 0.006, 0.004, 0, 0, 0}));

  const auto axis = vtp.get<double>("PointData/axis", "Float64", 3);
  const auto length = vtp.get<double>("PointData/length", "Float64", 1);
  const auto cap = vtp.get<double>("PointData/cap_radius", "Float64", 1);
  const auto cyl = vtp.get<double>("PointData/cylinder_scale", "Float64", 3);
  const auto off = vtp.get<double>("PointData/cap_offset", "Float64", 3);
  ASSERT_EQ(axis.size(), 3 * n);
  ASSERT_EQ(length.size(), n);
  ASSERT_EQ(cap.size(), n);
  ASSERT_EQ(cyl.size(), 3 * n);
  ASSERT_EQ(off.size(), 3 * n);
  const double c30 = std::cos(kPi / 6), s30 = std::sin(kPi / 6);
  const double c40 = std::cos(40 * kPi / 180), s40 = std::sin(40 * kPi / 180);
  const std::vector<Vec3> expected_axis = {
      {0, 0, 1},                              // sphere: body e_z, identity
      {0, -1, 0},                             // e_z turned 90 deg about x
      {s30 * c40, s30 * s40, c30},            // e_z -> (sin 30, 0, cos 30), then 40 deg about z
      {c30, s30, 0},                          // polygon: body e_x turned 30 deg about z
      {0, 1, 0},                              // disk: body e_x turned 90 deg about z
      {std::sqrt(0.5), -std::sqrt(0.5), 0}};  // polygon: -45 deg about z
  const std::vector<double> expected_cap = {0.004, 0.002, 0.001, 0, 0.006, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const double h = s.half_length()[i];
    EXPECT_NEAR(length[i], 2 * s.radius()[i], 1e-18) << i;
    EXPECT_NEAR(cap[i], expected_cap[i], 1e-18) << i;
    EXPECT_NEAR(cyl[3 * i + 0], 2 * h, 1e-18) << i;
    EXPECT_NEAR(cyl[3 * i + 1], 2 * expected_cap[i], 1e-18) << i;
    EXPECT_NEAR(cyl[3 * i + 2], 2 * expected_cap[i], 1e-18) << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(axis[3 * i + k], expected_axis[i][k], 1e-15) << i << " " << k;
      EXPECT_NEAR(off[3 * i + k], h * expected_axis[i][k], 1e-17) << i << " " << k;
    }
  }
  // A spherocylinder's length is tip to tip: 2 (half_length + r_cap).
  EXPECT_NEAR(length[1], 2 * (0.006 + 0.002), 1e-18);
}

TEST(OutputShapes, EmptyStoreWithShapesIsValid) {
  TempDir dir;
  ParticleStore s;
  s.enable_shapes();
  io::write_particles_vtp(dir / "p.vtp", s);
  const Vtp vtp(dir / "p.vtp");
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "0");
  EXPECT_TRUE(vtp.get<double>("PointData/orientation", "Float64", 4).empty());
  EXPECT_TRUE(vtp.get<double>("PointData/axis", "Float64", 3).empty());
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());
  io::write_polygons_vtp(dir / "g.vtp", s);
  const Vtp g(dir / "g.vtp");
  EXPECT_EQ(g.piece("NumberOfPolys"), "0");
  EXPECT_EQ(g.blocks_size(), g.appended.size());
}

TEST(OutputShapes, PolygonsVtpHasOnePolygonCellPerGrain) {
  TempDir dir;
  const ParticleStore s = shape_store();
  EXPECT_EQ(io::count_polygon_grains(s), 2u);
  io::write_polygons_vtp(dir / "g.vtp", s);
  const Vtp vtp(dir / "g.vtp");
  EXPECT_NE(vtp.header.find("type=\"PolyData\""), std::string::npos);
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "7");
  EXPECT_EQ(vtp.piece("NumberOfPolys"), "2");
  EXPECT_EQ(vtp.piece("NumberOfVerts"), "0");
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());
  std::vector<std::string> keys;
  for (const auto& [k, a] : vtp.arrays) keys.push_back(k);
  EXPECT_EQ(keys,
            (std::vector<std::string>{"CellData/angular_velocity", "CellData/area", "CellData/id",
                                      "CellData/material", "CellData/speed", "CellData/velocity",
                                      "Points/position", "Polys/connectivity", "Polys/offsets"}));

  EXPECT_EQ(vtp.get<std::int64_t>("Polys/connectivity", "Int64", 1),
            (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(vtp.get<std::int64_t>("Polys/offsets", "Int64", 1), (std::vector<std::int64_t>{4, 7}));
  EXPECT_EQ(vtp.get<std::int64_t>("CellData/id", "Int64", 1),
            (std::vector<std::int64_t>{103, 105}));
  EXPECT_EQ(vtp.get<std::int32_t>("CellData/material", "Int32", 1),
            (std::vector<std::int32_t>{2, 3}));
  EXPECT_EQ(vtp.get<double>("CellData/velocity", "Float64", 3),
            (std::vector<double>{0.5, -0.5, 0, -0.1, 0, 0}));
  EXPECT_EQ(vtp.get<double>("CellData/angular_velocity", "Float64", 3),
            (std::vector<double>{0, 0, -3, 0, 0, 0.5}));
  const auto speed = vtp.get<double>("CellData/speed", "Float64", 1);
  ASSERT_EQ(speed.size(), 2u);
  EXPECT_DOUBLE_EQ(speed[0], std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(speed[1], 0.1);
  EXPECT_EQ(vtp.get<double>("CellData/area", "Float64", 1),
            (std::vector<double>{s.polygons()[0].area, s.polygons()[1].area}));

  // World vertices: centre + body vertex turned about z (counter-clockwise kept).
  auto world = [](Vec3 c, double angle, double vx, double vy) {
    return Vec3{c.x + std::cos(angle) * vx - std::sin(angle) * vy,
                c.y + std::sin(angle) * vx + std::cos(angle) * vy, c.z};
  };
  std::vector<Vec3> expected;
  for (const auto& v : s.polygons()[0].body.v | std::views::take(4))
    expected.push_back(world({0.1, 0.05, 0}, kPi / 6, v.x, v.y));
  for (const auto& v : s.polygons()[1].body.v | std::views::take(3))
    expected.push_back(world({0.15, 0.02, 0}, -kPi / 4, v.x, v.y));
  const auto pts = vtp.get<double>("Points/position", "Float64", 3);
  ASSERT_EQ(pts.size(), 3 * expected.size());
  for (std::size_t j = 0; j < expected.size(); ++j)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(pts[3 * j + k], expected[j][k], 1e-15) << j;
}

TEST(OutputShapes, PolygonsVtpWithoutPolygonsIsEmpty) {
  TempDir dir;
  ParticleStore spheres;  // no shape fields at all
  spheres.add_sphere(1, 0, 0.01, 2500, {0, 0, 0});
  EXPECT_EQ(io::count_polygon_grains(spheres), 0u);
  io::write_polygons_vtp(dir / "g.vtp", spheres);
  const Vtp vtp(dir / "g.vtp");
  EXPECT_EQ(vtp.piece("NumberOfPoints"), "0");
  EXPECT_EQ(vtp.piece("NumberOfPolys"), "0");
  EXPECT_TRUE(vtp.get<std::int64_t>("CellData/id", "Int64", 1).empty());
  EXPECT_TRUE(vtp.get<std::int64_t>("Polys/offsets", "Int64", 1).empty());
  EXPECT_EQ(vtp.blocks_size(), vtp.appended.size());
}

TEST(OutputShapes, BadPolygonIndexIsAnErrorAndWritesNothing) {
  TempDir dir;
  std::ofstream(dir / "g.vtp") << "old";
  ParticleStore s = shape_store();
  s.polygon()[5] = 7;  // table of 2
  std::string what;
  try {
    io::write_polygons_vtp(dir / "g.vtp", s);
  } catch (const Error& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("id 105"), std::string::npos) << what;
  EXPECT_NE(what.find("polygon 7"), std::string::npos) << what;
  s.polygon()[5] = -1;
  EXPECT_THROW(io::write_polygons_vtp(dir / "g.vtp", s), Error);
  s.polygon()[5] = 1;
  s.polygons()[1].body.n = 2;  // degenerate
  EXPECT_THROW(io::write_polygons_vtp(dir / "g.vtp", s), Error);
  EXPECT_EQ(slurp(dir / "g.vtp"), "old");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"g.vtp"});
}

TEST(OutputShapes, CsvHasQuaternionAxisAndIntegerShapeColumns) {
  TempDir dir;
  const ParticleStore s = shape_store();
  EXPECT_EQ(fmt::format("{}", fmt::join(io::particle_csv_columns(s), ",")),
            "id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,shape,half_length,qw,qx,qy,qz,"
            "ax,ay,az,polygon");
  io::write_particles_csv(dir / "p.csv", s);
  std::istringstream in(slurp(dir / "p.csv"));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line);
  ASSERT_EQ(header.size(), 25u);
  std::map<std::string, std::size_t> col;
  for (std::size_t c = 0; c < header.size(); ++c) col[header[c]] = c;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) rows.push_back(split(line));
  ASSERT_EQ(rows.size(), s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto& r = rows[i];
    ASSERT_EQ(r.size(), header.size()) << i;
    // Integers as integers.
    EXPECT_EQ(r[col["id"]], std::to_string(s.id()[i]));
    EXPECT_EQ(r[col["material"]], std::to_string(s.material()[i]));
    EXPECT_EQ(r[col["shape"]], std::to_string(s.shape()[i]));
    EXPECT_EQ(r[col["polygon"]], std::to_string(s.polygon()[i]));
    // Reals read back exactly.
    auto num = [&](const char* name) { return std::strtod(r[col[name]].c_str(), nullptr); };
    EXPECT_EQ(num("half_length"), s.half_length()[i]);
    const Quat& q = s.orientation()[i];
    EXPECT_EQ(num("qw"), q.w);
    EXPECT_EQ(num("qx"), q.x);
    EXPECT_EQ(num("qy"), q.y);
    EXPECT_EQ(num("qz"), q.z);
    const Vec3 a = io::shape_axis(s.shape()[i], q);
    EXPECT_EQ(num("ax"), a.x);
    EXPECT_EQ(num("ay"), a.y);
    EXPECT_EQ(num("az"), a.z);
  }
  EXPECT_EQ(rows[1][col["shape"]], "1");
  EXPECT_EQ(rows[1][col["half_length"]], "0.006");
  EXPECT_EQ(rows[0][col["qw"]], "1");
  EXPECT_EQ(rows[0][col["qx"]], "0");
  EXPECT_NEAR(std::strtod(rows[1][col["ay"]].c_str(), nullptr), -1, 1e-15);
  EXPECT_EQ(rows[3][col["polygon"]], "0");
  EXPECT_EQ(rows[0][col["polygon"]], "-1");

  // Another quaternion field keeps the NAME_w.. naming; no axis columns after it.
  ParticleStore t;
  t.add_field("spin", FieldType::Quat, "1", kOutput);
  t.add_sphere(1, 0, 0.01, 2500, {0, 0, 0});
  EXPECT_EQ(fmt::format("{}", fmt::join(io::particle_csv_columns(t), ",")),
            "id,material,radius,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,spin_w,spin_x,spin_y,spin_z");
  io::write_particles_csv(dir / "t.csv", t);
  const std::string text = slurp(dir / "t.csv");
  EXPECT_EQ(text.substr(text.find('\n') + 1), "1,0,0.01,0,0,0,0,0,0,0,0,0,0,0,0,1,0,0,0\n");
}

// Writes a small sample series for tests/python/test_vtk_readback.py when GF_SAMPLE_OUTPUT_DIR
// is set (until `grainflow run` produces output itself).
TEST(OutputSample, WritesSeriesForPythonReadback) {
  const char* out = std::getenv("GF_SAMPLE_OUTPUT_DIR");
  if (!out || !*out) GTEST_SKIP() << "GF_SAMPLE_OUTPUT_DIR not set";
  const fs::path dir(out);
  fs::create_directories(dir);
  io::PvdSeries particles(dir / "particles.pvd"), walls(dir / "walls.pvd");
  ParticleStore s;
  for (int i = 0; i < 4; ++i)
    s.add_sphere(100 + i, 0, 0.005, 2500, {0.012 * i, 0, 0.006 + 0.01 * i}, {0, 0, -0.1 * i});
  const std::vector<SurfaceMesh> meshes = {
      {"floor",
       {{-0.05, -0.05, 0}, {0.05, -0.05, 0}, {0.05, 0.05, 0}, {-0.05, 0.05, 0}},
       {{0, 1, 2}, {0, 2, 3}}}};
  for (int step = 0; step < 3; ++step) {
    const double t = 0.005 * step;
    for (std::size_t i = 0; i < s.size(); ++i) s.x()[i].z -= 0.001 * step;
    const std::string p = fmt::format("particles_{:06d}.vtp", step),
                      w = fmt::format("walls_{:06d}.vtp", step);
    io::write_particles_vtp(dir / p, s);
    particles.add(t, p);
    const Vec3 force{0, 0, 0.5 * step};
    io::write_surfaces_vtp(dir / w, meshes, std::span(&force, 1));
    walls.add(t, w);
  }
  io::write_particles_csv(dir / "particles.csv", s);
}

// Writes the shape sample for tests/python/test_vtk_shapes.py (which runs this test with
// GF_SAMPLE_OUTPUT_DIR set): two output steps of shape_store() as particles_*.vtp,
// polygons_*.vtp with their .pvd series, and particles.csv. Between the steps every grain turns
// by 90 degrees about z, so step 1 checks a second orientation.
TEST(OutputSample, WritesShapeSampleForPythonReadback) {
  const char* out = std::getenv("GF_SAMPLE_OUTPUT_DIR");
  if (!out || !*out) GTEST_SKIP() << "GF_SAMPLE_OUTPUT_DIR not set";
  const fs::path dir(out);
  fs::create_directories(dir);
  io::PvdSeries particles(dir / "particles.pvd"), polygons(dir / "polygons.pvd");
  ParticleStore s = shape_store();
  const Quat turn = quat_from_axis_angle({0, 0, 1}, kPi / 2);
  for (int step = 0; step < 2; ++step) {
    if (step > 0)
      for (std::size_t i = 0; i < s.size(); ++i) s.orientation()[i] = turn * s.orientation()[i];
    const double t = 0.01 * step;
    const std::string p = fmt::format("particles_{:06d}.vtp", step),
                      g = fmt::format("polygons_{:06d}.vtp", step);
    io::write_particles_vtp(dir / p, s);
    particles.add(t, p);
    io::write_polygons_vtp(dir / g, s);
    polygons.add(t, g);
    io::write_particles_csv(dir / fmt::format("particles_{:06d}.csv", step), s);
  }
}

namespace gf {
namespace {

// The continuum runs' output schedule: steps land on output times (until), each output falls
// due once per period however the steps fall, 0 means every step / only at the end / never.
TEST(OutputClock, LandsOnOutputTimesAndFallsDueOncePerPeriod) {
  OutputClock clock({0.1, 0.025, 0.3}, 1.0);
  EXPECT_DOUBLE_EQ(clock.until(), 0.025);
  int series = 0, vtk = 0, checkpoints = 0;
  double t = 0.0;
  while (!clock.finished(t)) {
    t = std::min(t + 0.0071, clock.until());  // steps that do not divide the periods
    series += clock.series_due(t);
    vtk += clock.vtk_due(t);
    checkpoints += clock.checkpoint_due(t);
  }
  EXPECT_DOUBLE_EQ(t, 1.0);
  EXPECT_EQ(series, 40);
  EXPECT_EQ(vtk, 10);
  EXPECT_EQ(checkpoints, 3);  // 0.3, 0.6, 0.9
  // Zeros: a series row every step, a snapshot only at the end, no checkpoint.
  OutputClock zero({0.0, 0.0, 0.0}, 2.0);
  EXPECT_DOUBLE_EQ(zero.until(), 2.0);
  EXPECT_TRUE(zero.series_due(0.5));
  EXPECT_TRUE(zero.series_due(0.6));
  EXPECT_FALSE(zero.vtk_due(1.9));
  EXPECT_TRUE(zero.vtk_due(2.0 - 1e-13));  // within 1e-12 of the end time
  EXPECT_FALSE(zero.checkpoint_due(2.0));
  EXPECT_TRUE(zero.finished(2.0));
}

}  // namespace
}  // namespace gf
