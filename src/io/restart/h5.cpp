// SPDX-License-Identifier: GPL-3.0-or-later
// HDF5 wrapper (handles, datasets, attributes, errors as IoError) and particle checkpoints.
#include "io/restart/h5.hpp"

#include <fmt/ranges.h>
#include <hdf5.h>

#include <algorithm>
#include <type_traits>
#include <utility>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/version.hpp"

namespace gf::io {

namespace h5 {

namespace fs = std::filesystem;

static_assert(std::is_same_v<hid_t, std::int64_t>, "HDF5 >= 1.10 uses 64-bit hid_t");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
static_assert(sizeof(Quat) == 4 * sizeof(double), "Quat must be four packed doubles");

namespace {

/// Owns one HDF5 identifier and closes it with the matching H5*close function.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), closer_(o.closer_) {}
  Handle& operator=(Handle&& o) noexcept {
    std::swap(id_, o.id_);
    std::swap(closer_, o.closer_);
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0 && closer_) closer_(id_);
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

/// Turns off HDF5's printing of its error stack; failures are reported by exceptions instead.
/// The setting is per thread in thread-safe builds, hence thread_local.
void quiet() {
  thread_local bool done = false;
  if (!done) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    done = true;
  }
}

/// The innermost message of HDF5's current error stack (then clears it); empty when none.
std::string hdf5_detail() {
  std::string innermost;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* err, void* data) -> herr_t {
        if (err && err->desc && *err->desc) *static_cast<std::string*>(data) = err->desc;
        return 0;
      },
      &innermost);
  H5Eclear2(H5E_DEFAULT);
  return innermost.empty() ? std::string() : fmt::format(" (HDF5: {})", innermost);
}

[[noreturn]] void fail(const fs::path& file, const std::string& object, const std::string& what) {
  const std::string detail = hdf5_detail();
  if (object.empty())
    throw IoError(fmt::format("HDF5 file '{}': {}{}", file.string(), what, detail));
  throw IoError(
      fmt::format("HDF5 file '{}', object '{}': {}{}", file.string(), object, what, detail));
}

/// "a/b/" -> "a/b"; "" or "/" -> "/" (the root).
std::string normalize(const std::string& object) {
  std::size_t b = object.find_first_not_of('/');
  if (b == std::string::npos) return "/";
  std::size_t e = object.find_last_not_of('/');
  return object.substr(b, e - b + 1);
}

/// Link-creation property list that creates missing parent groups.
Handle intermediate_lcpl(const fs::path& file, const std::string& object) {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (!lcpl.valid() || H5Pset_create_intermediate_group(lcpl.get(), 1) < 0)
    fail(file, object, "cannot create a link property list");
  return lcpl;
}

DatasetInfo::Class class_of(hid_t type) {
  switch (H5Tget_class(type)) {
    case H5T_FLOAT:
      return DatasetInfo::Class::Float;
    case H5T_INTEGER:
      return DatasetInfo::Class::Integer;
    default:
      return DatasetInfo::Class::Other;
  }
}

const char* class_name(DatasetInfo::Class c) {
  switch (c) {
    case DatasetInfo::Class::Float:
      return "floating point";
    case DatasetInfo::Class::Integer:
      return "integer";
    default:
      return "other";
  }
}

}  // namespace

// ---- File -----------------------------------------------------------------------------------

File File::create(const fs::path& path) {
  quiet();
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.valid() || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0)
    fail(path, "", "cannot create a file access property list");
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (id < 0) fail(path, "", "cannot create the file");
  return File(id, path);
}

File File::open_read(const fs::path& path) {
  quiet();
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw IoError(fmt::format("HDF5 file '{}' does not exist", path.string()));
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.valid() || H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG) < 0)
    fail(path, "", "cannot create a file access property list");
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get());
  if (id < 0) fail(path, "", "cannot open the file (not an HDF5 file?)");
  return File(id, path);
}

File::File(File&& other) noexcept
    : id_(std::exchange(other.id_, -1)), path_(std::move(other.path_)) {}

File& File::operator=(File&& other) noexcept {
  std::swap(id_, other.id_);
  std::swap(path_, other.path_);
  return *this;
}

File::~File() {
  if (id_ >= 0) H5Fclose(id_);
}

void File::close() {
  if (id_ < 0) return;
  const hid_t id = std::exchange(id_, -1);
  if (H5Fclose(id) < 0) fail(path_, "", "error while closing the file");
}

hid_t File::checked_id(const std::string& object) const {
  quiet();
  if (id_ < 0)
    throw IoError(
        fmt::format("HDF5 file '{}', object '{}': the file is closed", path_.string(), object));
  return id_;
}

hid_t File::open_object(const std::string& object) const {
  const hid_t file = checked_id(object);
  const std::string name = normalize(object);
  if (!exists(name)) fail(path_, name, "no such group or dataset");
  const hid_t obj = H5Oopen(file, name.c_str(), H5P_DEFAULT);
  if (obj < 0) fail(path_, name, "cannot open");
  return obj;
}

bool File::exists(const std::string& object) const {
  const hid_t file = checked_id(object);
  const std::string name = normalize(object);
  if (name == "/") return true;
  std::size_t pos = 0;
  while (true) {
    const std::size_t slash = name.find('/', pos);
    const std::string prefix = name.substr(0, slash);
    const htri_t e = H5Lexists(file, prefix.c_str(), H5P_DEFAULT);
    if (e <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (slash == std::string::npos) return true;
    // Intermediate components must be groups for the next lookup to make sense.
    Handle obj(H5Oopen(file, prefix.c_str(), H5P_DEFAULT), H5Oclose);
    if (!obj.valid() || H5Iget_type(obj.get()) != H5I_GROUP) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    pos = slash + 1;
  }
}

bool File::is_group(const std::string& object) const {
  if (!exists(object)) return false;
  Handle obj(open_object(object), H5Oclose);
  return H5Iget_type(obj.get()) == H5I_GROUP;
}

void File::create_group(const std::string& group) {
  const hid_t file = checked_id(group);
  const std::string name = normalize(group);
  if (exists(name)) {
    if (!is_group(name)) fail(path_, name, "exists and is not a group");
    return;
  }
  Handle lcpl = intermediate_lcpl(path_, name);
  Handle g(H5Gcreate2(file, name.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(path_, name, "cannot create the group");
}

std::vector<std::string> File::list(const std::string& group) const {
  checked_id(group);
  const std::string name = normalize(group);
  if (!is_group(name)) fail(path_, name, "is not a group");
  Handle g(H5Gopen2(id_, name.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(path_, name, "cannot open the group");
  H5G_info_t gi;
  if (H5Gget_info(g.get(), &gi) < 0) fail(path_, name, "cannot query the group");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < gi.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail(path_, name, "cannot list the group");
    std::string s(static_cast<std::size_t>(len) + 1, '\0');
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, s.data(), s.size(),
                       H5P_DEFAULT);
    s.resize(static_cast<std::size_t>(len));
    names.push_back(std::move(s));
  }
  return names;
}

// ---- datasets -------------------------------------------------------------------------------

namespace {

/// Creates (replacing any existing link of that name) and fills a dataset of n rows of ncomp
/// values (ncomp == 0: 1-D).
void write_dataset(const File& f, hid_t file, const std::string& object, hid_t mem_type,
                   hid_t file_type, std::size_t n, std::size_t ncomp, const void* data) {
  const std::string name = normalize(object);
  if (name == "/") fail(f.path(), name, "the root cannot be a dataset");
  if (f.exists(name) && H5Ldelete(file, name.c_str(), H5P_DEFAULT) < 0)
    fail(f.path(), name, "cannot replace the existing dataset");
  const hsize_t dims[2] = {static_cast<hsize_t>(n), static_cast<hsize_t>(ncomp)};
  Handle space(H5Screate_simple(ncomp == 0 ? 1 : 2, dims, nullptr), H5Sclose);
  if (!space.valid()) fail(f.path(), name, "cannot create a dataspace");
  Handle lcpl = intermediate_lcpl(f.path(), name);
  // Chunks of about 1 MiB, each with a Fletcher-32 checksum that HDF5 checks on every read: a
  // damaged file is refused instead of restarting from wrong numbers. (Files of earlier builds,
  // without checksums, read as before.)
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!dcpl.valid()) fail(f.path(), name, "cannot create a dataset property list");
  if (n > 0) {
    const std::size_t row_bytes = H5Tget_size(file_type) * std::max<std::size_t>(ncomp, 1);
    const hsize_t chunk[2] = {
        std::min<hsize_t>(dims[0], std::max<hsize_t>(1, (std::size_t{1} << 20) / row_bytes)),
        dims[1]};
    if (H5Pset_chunk(dcpl.get(), ncomp == 0 ? 1 : 2, chunk) < 0 ||
        H5Pset_fletcher32(dcpl.get()) < 0)
      fail(f.path(), name, "cannot set the dataset's checksum");
  }
  Handle dset(
      H5Dcreate2(file, name.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
      H5Dclose);
  if (!dset.valid()) fail(f.path(), name, "cannot create the dataset");
  if (n > 0 && H5Dwrite(dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail(f.path(), name, "cannot write the dataset");
}

/// Reads a whole dataset into `out` (n rows of ncomp values; ncomp == 0: 1-D) after checking
/// its class, element size (no narrowing) and shape.
void read_dataset(const File& f, hid_t file, const std::string& object, hid_t mem_type,
                  DatasetInfo::Class want, std::size_t n, std::size_t ncomp, void* out) {
  const std::string name = normalize(object);
  const DatasetInfo info = f.info(name);
  if (info.type_class != want)
    fail(
        f.path(), name,
        fmt::format("holds {} values, expected {}", class_name(info.type_class), class_name(want)));
  if (info.type_size > H5Tget_size(mem_type))
    fail(f.path(), name,
         fmt::format("holds {}-byte values, too wide for {}-byte storage", info.type_size,
                     H5Tget_size(mem_type)));
  const std::size_t rank = ncomp == 0 ? 1 : 2;
  if (info.shape.size() != rank || (rank == 2 && info.shape[1] != ncomp))
    fail(f.path(), name,
         fmt::format("has shape [{}], expected {}", fmt::join(info.shape, ", "),
                     rank == 1 ? std::string("[N]") : fmt::format("[N, {}]", ncomp)));
  if (info.shape[0] != n)
    fail(f.path(), name, fmt::format("has {} rows, expected {}", info.shape[0], n));
  if (n == 0) return;
  Handle dset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dset.valid()) fail(f.path(), name, "cannot open the dataset");
  if (H5Dread(dset.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    fail(f.path(), name, "cannot read the dataset (the file is damaged if its checksum failed)");
}

}  // namespace

void File::write(const std::string& dataset, std::span<const double> data) {
  write_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, data.size(),
                0, data.data());
}
void File::write(const std::string& dataset, std::span<const std::int64_t> data) {
  write_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_INT64, H5T_STD_I64LE, data.size(),
                0, data.data());
}
void File::write(const std::string& dataset, std::span<const std::int32_t> data) {
  write_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_INT32, H5T_STD_I32LE, data.size(),
                0, data.data());
}
void File::write(const std::string& dataset, std::span<const std::uint8_t> data) {
  write_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_UINT8, H5T_STD_U8LE, data.size(), 0,
                data.data());
}
void File::write(const std::string& dataset, std::span<const Vec3> data) {
  write_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, data.size(),
                3, data.data());
}
void File::write(const std::string& dataset, std::span<const Quat> data) {
  write_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, data.size(),
                4, data.data());
}

DatasetInfo File::info(const std::string& dataset) const {
  const hid_t file = checked_id(dataset);
  const std::string name = normalize(dataset);
  if (!exists(name)) fail(path_, name, "no such dataset");
  Handle dset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dset.valid()) fail(path_, name, "is not a dataset");
  Handle type(H5Dget_type(dset.get()), H5Tclose);
  Handle space(H5Dget_space(dset.get()), H5Sclose);
  if (!type.valid() || !space.valid()) fail(path_, name, "cannot query the dataset");
  DatasetInfo info;
  info.type_class = class_of(type.get());
  info.type_size = H5Tget_size(type.get());
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) fail(path_, name, "cannot query the dataspace");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
    fail(path_, name, "cannot query the dataspace");
  info.shape.assign(dims.begin(), dims.end());
  return info;
}

namespace {
std::size_t rows_of(const File& f, const std::string& dataset) {
  const DatasetInfo info = f.info(dataset);
  return info.shape.empty() ? 0 : static_cast<std::size_t>(info.shape[0]);
}
}  // namespace

void File::read(const std::string& dataset, std::span<double> out) const {
  read_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_DOUBLE, DatasetInfo::Class::Float,
               out.size(), 0, out.data());
}
void File::read(const std::string& dataset, std::span<std::int64_t> out) const {
  read_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_INT64, DatasetInfo::Class::Integer,
               out.size(), 0, out.data());
}
void File::read(const std::string& dataset, std::span<std::int32_t> out) const {
  read_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_INT32, DatasetInfo::Class::Integer,
               out.size(), 0, out.data());
}
void File::read(const std::string& dataset, std::span<std::uint8_t> out) const {
  read_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_UINT8, DatasetInfo::Class::Integer,
               out.size(), 0, out.data());
}
void File::read(const std::string& dataset, std::span<Vec3> out) const {
  read_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_DOUBLE, DatasetInfo::Class::Float,
               out.size(), 3, out.data());
}
void File::read(const std::string& dataset, std::span<Quat> out) const {
  read_dataset(*this, checked_id(dataset), dataset, H5T_NATIVE_DOUBLE, DatasetInfo::Class::Float,
               out.size(), 4, out.data());
}

std::vector<double> File::read_double(const std::string& dataset) const {
  std::vector<double> v(rows_of(*this, dataset));
  read(dataset, std::span<double>(v));
  return v;
}
std::vector<std::int64_t> File::read_int64(const std::string& dataset) const {
  std::vector<std::int64_t> v(rows_of(*this, dataset));
  read(dataset, std::span<std::int64_t>(v));
  return v;
}
std::vector<std::int32_t> File::read_int32(const std::string& dataset) const {
  std::vector<std::int32_t> v(rows_of(*this, dataset));
  read(dataset, std::span<std::int32_t>(v));
  return v;
}
std::vector<std::uint8_t> File::read_uint8(const std::string& dataset) const {
  std::vector<std::uint8_t> v(rows_of(*this, dataset));
  read(dataset, std::span<std::uint8_t>(v));
  return v;
}
std::vector<Vec3> File::read_vec3(const std::string& dataset) const {
  std::vector<Vec3> v(rows_of(*this, dataset));
  read(dataset, std::span<Vec3>(v));
  return v;
}

// ---- attributes -----------------------------------------------------------------------------

namespace {

/// Opens the object an attribute lives on and removes an existing attribute of that name.
Handle open_for_attribute(const File& f, hid_t obj, const std::string& object,
                          const std::string& name) {
  Handle h(obj, H5Oclose);
  const htri_t e = H5Aexists(h.get(), name.c_str());
  if (e < 0) fail(f.path(), object, fmt::format("cannot query attribute '{}'", name));
  if (e > 0 && H5Adelete(h.get(), name.c_str()) < 0)
    fail(f.path(), object, fmt::format("cannot replace attribute '{}'", name));
  return h;
}

void write_attribute(const File& f, hid_t obj_id, const std::string& object,
                     const std::string& name, hid_t mem_type, hid_t file_type, const void* value) {
  Handle obj = open_for_attribute(f, obj_id, object, name);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (!space.valid()) fail(f.path(), object, "cannot create a dataspace");
  Handle attr(H5Acreate2(obj.get(), name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose);
  if (!attr.valid()) fail(f.path(), object, fmt::format("cannot create attribute '{}'", name));
  if (H5Awrite(attr.get(), mem_type, value) < 0)
    fail(f.path(), object, fmt::format("cannot write attribute '{}'", name));
}

/// Opens attribute `name` of `obj_id` (taking ownership of it) and checks it holds one value.
std::pair<Handle, Handle> open_attribute(const File& f, hid_t obj_id, const std::string& object,
                                         const std::string& name) {
  Handle obj(obj_id, H5Oclose);
  const htri_t e = H5Aexists(obj.get(), name.c_str());
  if (e <= 0) fail(f.path(), object, fmt::format("has no attribute '{}'", name));
  Handle attr(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) fail(f.path(), object, fmt::format("cannot open attribute '{}'", name));
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  if (!space.valid() || H5Sget_simple_extent_npoints(space.get()) != 1)
    fail(f.path(), object, fmt::format("attribute '{}' is not a single value", name));
  return {std::move(obj), std::move(attr)};
}

}  // namespace

void File::set_attribute(const std::string& object, const std::string& name,
                         const std::string& value) {
  const std::string obj_name = normalize(object);
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), value.size() + 1) < 0 ||
      H5Tset_strpad(type.get(), H5T_STR_NULLTERM) < 0 || H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    fail(path_, obj_name, "cannot create a string type");
  write_attribute(*this, open_object(obj_name), obj_name, name, type.get(), type.get(),
                  value.c_str());
}

void File::set_attribute(const std::string& object, const std::string& name, const char* value) {
  set_attribute(object, name, std::string(value));
}

void File::set_attribute(const std::string& object, const std::string& name, double value) {
  const std::string obj_name = normalize(object);
  write_attribute(*this, open_object(obj_name), obj_name, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE,
                  &value);
}

void File::set_attribute(const std::string& object, const std::string& name, std::int64_t value) {
  const std::string obj_name = normalize(object);
  write_attribute(*this, open_object(obj_name), obj_name, name, H5T_NATIVE_INT64, H5T_STD_I64LE,
                  &value);
}

void File::set_attribute(const std::string& object, const std::string& name, std::int32_t value) {
  const std::string obj_name = normalize(object);
  write_attribute(*this, open_object(obj_name), obj_name, name, H5T_NATIVE_INT32, H5T_STD_I32LE,
                  &value);
}

bool File::has_attribute(const std::string& object, const std::string& name) const {
  const std::string obj_name = normalize(object);
  if (!exists(obj_name)) return false;
  Handle obj(open_object(obj_name), H5Oclose);
  const htri_t e = H5Aexists(obj.get(), name.c_str());
  if (e < 0) fail(path_, obj_name, fmt::format("cannot query attribute '{}'", name));
  return e > 0;
}

std::string File::read_string_attribute(const std::string& object, const std::string& name) const {
  const std::string obj_name = normalize(object);
  auto [obj, attr] = open_attribute(*this, open_object(obj_name), obj_name, name);
  Handle ftype(H5Aget_type(attr.get()), H5Tclose);
  if (!ftype.valid() || H5Tget_class(ftype.get()) != H5T_STRING)
    fail(path_, obj_name, fmt::format("attribute '{}' is not a string", name));
  Handle mtype(H5Tcopy(H5T_C_S1), H5Tclose);
  // HDF5 converts only between strings of the same character set.
  if (!mtype.valid() || H5Tset_cset(mtype.get(), H5Tget_cset(ftype.get())) < 0)
    fail(path_, obj_name, "cannot create a string type");
  if (H5Tis_variable_str(ftype.get()) > 0) {
    if (H5Tset_size(mtype.get(), H5T_VARIABLE) < 0)
      fail(path_, obj_name, "cannot create a string type");
    char* s = nullptr;
    if (H5Aread(attr.get(), mtype.get(), &s) < 0)
      fail(path_, obj_name, fmt::format("cannot read attribute '{}'", name));
    std::string out = s ? s : "";
    H5free_memory(s);
    return out;
  }
  const std::size_t size = H5Tget_size(ftype.get());
  if (H5Tset_size(mtype.get(), size) < 0) fail(path_, obj_name, "cannot create a string type");
  std::string buf(size, '\0');
  if (H5Aread(attr.get(), mtype.get(), buf.data()) < 0)
    fail(path_, obj_name, fmt::format("cannot read attribute '{}'", name));
  buf.resize(std::min(buf.find('\0'), buf.size()));
  return buf;
}

double File::read_double_attribute(const std::string& object, const std::string& name) const {
  const std::string obj_name = normalize(object);
  auto [obj, attr] = open_attribute(*this, open_object(obj_name), obj_name, name);
  Handle ftype(H5Aget_type(attr.get()), H5Tclose);
  const DatasetInfo::Class c = ftype.valid() ? class_of(ftype.get()) : DatasetInfo::Class::Other;
  if (c == DatasetInfo::Class::Other)
    fail(path_, obj_name, fmt::format("attribute '{}' is not a number", name));
  double v = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v) < 0)
    fail(path_, obj_name, fmt::format("cannot read attribute '{}'", name));
  return v;
}

std::int64_t File::read_int_attribute(const std::string& object, const std::string& name) const {
  const std::string obj_name = normalize(object);
  auto [obj, attr] = open_attribute(*this, open_object(obj_name), obj_name, name);
  Handle ftype(H5Aget_type(attr.get()), H5Tclose);
  if (!ftype.valid() || class_of(ftype.get()) != DatasetInfo::Class::Integer)
    fail(path_, obj_name, fmt::format("attribute '{}' is not an integer", name));
  std::int64_t v = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_INT64, &v) < 0)
    fail(path_, obj_name, fmt::format("cannot read attribute '{}'", name));
  return v;
}

}  // namespace h5

// ---- particle checkpoints -------------------------------------------------------------------

namespace {

constexpr std::size_t kPolygonRow = 1 + 2 * kMaxPolygonVertices + 4;

std::string join(const std::string& group, const std::string& name) {
  const std::size_t e = group.find_last_not_of('/');
  if (e == std::string::npos) return name;
  return group.substr(0, e + 1) + "/" + name;
}

const char* type_name(FieldType t) {
  switch (t) {
    case FieldType::Real:
      return "real";
    case FieldType::Vec3:
      return "vec3";
    case FieldType::Int64:
      return "int64";
    case FieldType::Int32:
      return "int32";
    case FieldType::Quat:
      return "quaternion";
  }
  return "?";
}

/// Whether a dataset's element type and rank can hold field type `t` bit-exactly.
bool matches(const h5::DatasetInfo& info, FieldType t) {
  using C = h5::DatasetInfo::Class;
  switch (t) {
    case FieldType::Real:
      return info.type_class == C::Float && info.type_size == 8 && info.shape.size() == 1;
    case FieldType::Vec3:
      return info.type_class == C::Float && info.type_size == 8 && info.shape.size() == 2 &&
             info.shape[1] == 3;
    case FieldType::Int64:
      return info.type_class == C::Integer && info.type_size == 8 && info.shape.size() == 1;
    case FieldType::Int32:
      return info.type_class == C::Integer && info.type_size == 4 && info.shape.size() == 1;
    case FieldType::Quat:
      return info.type_class == C::Float && info.type_size == 8 && info.shape.size() == 2 &&
             info.shape[1] == 4;
  }
  return false;
}

[[noreturn]] void type_mismatch(const h5::File& file, const std::string& ds, const FieldInfo& fi,
                                const h5::DatasetInfo& info) {
  throw IoError(fmt::format(
      "HDF5 file '{}', dataset '{}': particle field '{}' is {} but the file holds {}-byte {} "
      "values of shape [{}]",
      file.path().string(), ds, fi.name, type_name(fi.type), info.type_size,
      info.type_class == h5::DatasetInfo::Class::Float     ? "floating point"
      : info.type_class == h5::DatasetInfo::Class::Integer ? "integer"
                                                           : "non-numeric",
      fmt::join(info.shape, ", ")));
}

}  // namespace

void save_particles(h5::File& file, const ParticleStore& store, const std::string& group) {
  file.create_group(group);
  file.set_attribute(group, "count", static_cast<std::int64_t>(store.size()));
  const auto& fields = store.fields();
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const FieldInfo& fi = fields[f];
    if (!(fi.flags & kRestart)) continue;
    const std::string ds = join(group, fi.name);
    std::visit([&](const auto& col) { file.write(ds, std::span(col)); },
               store.column(static_cast<int>(f)));
    file.set_attribute(ds, "unit", fi.unit);
    file.set_attribute(ds, "type", type_name(fi.type));
  }
  if (!store.polygons().empty()) {
    // One row per body-frame polygon: n, 16 (x, y) pairs, area, equivalent radius,
    // circumradius, polar moment.
    std::vector<double> flat;
    flat.reserve(store.polygons().size() * kPolygonRow);
    for (const PolygonShape& p : store.polygons()) {
      flat.push_back(p.body.n);
      for (int k = 0; k < kMaxPolygonVertices; ++k) {
        flat.push_back(p.body.v[k].x);
        flat.push_back(p.body.v[k].y);
      }
      for (double d : {p.area, p.equivalent_radius, p.circumradius, p.polar_moment})
        flat.push_back(d);
    }
    const std::string ds = join(group, "polygon_table");
    file.write(ds, std::span<const double>(flat));
    file.set_attribute(ds, "row_length", static_cast<std::int64_t>(kPolygonRow));
  }
}

void load_particles(h5::File& file, ParticleStore& store, const std::string& group) {
  if (!file.is_group(group))
    throw IoError(
        fmt::format("HDF5 file '{}': no particle group '{}'", file.path().string(), group));
  const std::int64_t count = file.read_int_attribute(group, "count");
  if (count < 0)
    throw IoError(fmt::format("HDF5 file '{}', group '{}': negative particle count {}",
                              file.path().string(), group, count));
  const auto n = static_cast<std::size_t>(count);
  const auto& fields = store.fields();

  // Read everything first, so a failed load leaves the store untouched.
  std::vector<std::pair<int, Column>> loaded;
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const FieldInfo& fi = fields[f];
    if (!(fi.flags & kRestart)) continue;
    const std::string ds = join(group, fi.name);
    if (!file.exists(ds))
      throw IoError(fmt::format("HDF5 file '{}': particle field '{}' missing (no dataset '{}')",
                                file.path().string(), fi.name, ds));
    const h5::DatasetInfo info = file.info(ds);
    if (!matches(info, fi.type)) type_mismatch(file, ds, fi, info);
    // An empty column of the same alternative as the store's.
    Column col = std::visit([](const auto& v) { return Column(std::decay_t<decltype(v)>{}); },
                            store.column(static_cast<int>(f)));
    std::visit(
        [&](auto& v) {
          v.assign(n, {});
          file.read(ds, std::span(v));
        },
        col);
    loaded.emplace_back(static_cast<int>(f), std::move(col));
  }
  // Extra datasets are ignored unless they clash in type with a store field of the same name.
  for (const std::string& name : file.list(group)) {
    const int f = store.find_field(name);
    if (f < 0 || (fields[static_cast<std::size_t>(f)].flags & kRestart)) continue;
    const std::string ds = join(group, name);
    if (file.is_group(ds)) continue;
    const h5::DatasetInfo info = file.info(ds);
    if (!matches(info, fields[static_cast<std::size_t>(f)].type))
      type_mismatch(file, ds, fields[static_cast<std::size_t>(f)], info);
  }

  std::vector<PolygonShape> polygons;
  const std::string table = join(group, "polygon_table");
  if (file.exists(table)) {
    const std::vector<double> flat = file.read_double(table);
    if (file.read_int_attribute(table, "row_length") != static_cast<std::int64_t>(kPolygonRow) ||
        flat.size() % kPolygonRow != 0)
      throw IoError(fmt::format("HDF5 file '{}', dataset '{}': malformed polygon table",
                                file.path().string(), table));
    for (std::size_t row = 0; row < flat.size(); row += kPolygonRow) {
      PolygonShape p;
      const double* d = flat.data() + row;
      p.body.n = static_cast<int>(d[0]);
      if (p.body.n < 3 || p.body.n > kMaxPolygonVertices)
        throw IoError(fmt::format("HDF5 file '{}', dataset '{}': polygon with {} vertices",
                                  file.path().string(), table, p.body.n));
      for (int k = 0; k < kMaxPolygonVertices; ++k) p.body.v[k] = {d[1 + 2 * k], d[2 + 2 * k]};
      const double* t = d + 1 + 2 * kMaxPolygonVertices;
      p.area = t[0];
      p.equivalent_radius = t[1];
      p.circumradius = t[2];
      p.polar_moment = t[3];
      polygons.push_back(p);
    }
  }

  store.resize(0);  // fields not in the checkpoint restart from zero
  store.resize(n);
  for (auto& [f, col] : loaded) store.column(f) = std::move(col);
  store.polygons() = std::move(polygons);
}

void set_checkpoint_identity(h5::File& file, const std::string& kind) {
  file.set_attribute("/", "program", "grainflow");
  file.set_attribute("/", "version", version_string);
  if (!kind.empty()) file.set_attribute("/", "kind", kind);
}

std::string checkpoint_kind(const h5::File& file, const std::filesystem::path& path) {
  if (!file.has_attribute("/", "program") ||
      file.read_string_attribute("/", "program") != "grainflow")
    throw InputError(fmt::format("{}: not a grainflow checkpoint", path.string()));
  return file.has_attribute("/", "kind") ? file.read_string_attribute("/", "kind") : "";
}

void write_checkpoint_atomically(const std::filesystem::path& path,
                                 const std::function<void(h5::File&)>& fill) {
  write_atomically_path(path, [&](const std::filesystem::path& tmp) {
    h5::File file = h5::File::create(tmp);
    fill(file);
    file.close();
  });
}

}  // namespace gf::io
