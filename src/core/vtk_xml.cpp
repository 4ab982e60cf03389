// SPDX-License-Identifier: GPL-3.0-or-later
// VTK XML building blocks: appended raw binary arrays, the file's opening tag, .pvd collections.
#include "core/vtk_xml.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "core/files.hpp"

namespace gf::vtk {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "mixed-endian machines are not supported");

const char* byte_order() {
  return std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
}

std::string file_open(const char* type) {
  return fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"{}\" "
      "header_type=\"UInt64\">\n",
      type, byte_order());
}

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

const AppendedArrays::Array& AppendedArrays::add(const std::string& name,
                                                 std::span<const Vec3> values) {
  const auto* p = reinterpret_cast<const double*>(values.data());
  return add(name, 3, std::span<const double>(p, 3 * values.size()));
}

std::string AppendedArrays::tag(const Array& a) {
  return fmt::format(
      "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" "
      "offset=\"{}\"/>",
      a.type, xml_escape(a.name), a.n_components, a.offset);
}

void write_image_data(std::ostream& out, const std::array<int, 3>& n, const Vec3& origin,
                      const Vec3& spacing, const AppendedArrays& arrays, const std::string& tags,
                      const std::string& cell_attributes) {
  const std::string extent = fmt::format("0 {} 0 {} 0 {}", n[0], n[1], n[2]);
  out << file_open("ImageData")
      << fmt::format(
             "  <ImageData WholeExtent=\"{}\" Origin=\"{:.17g} {:.17g} {:.17g}\" "
             "Spacing=\"{:.17g} {:.17g} {:.17g}\">\n",
             extent, origin.x, origin.y, origin.z, spacing.x, spacing.y, spacing.z)
      << fmt::format("    <Piece Extent=\"{}\">\n", extent) << "      <CellData" << cell_attributes
      << ">\n"
      << tags << "      </CellData>\n    </Piece>\n  </ImageData>\n";
  arrays.write_appended(out);
  out << "</VTKFile>\n";
}

void AppendedArrays::write_appended(std::ostream& out) const {
  out << "  <AppendedData encoding=\"raw\">\n   _";
  for (const Array& a : arrays_) {
    const std::uint64_t n = a.n_bytes;
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    if (n > 0) out.write(static_cast<const char*>(a.data), static_cast<std::streamsize>(n));
  }
  out << "\n  </AppendedData>\n";
}

PvdSeries::PvdSeries(std::filesystem::path pvd_file) : path_(std::move(pvd_file)) {}

namespace {

/// Value of attribute `name` in one XML element's text, entities decoded; nullopt if absent.
std::optional<std::string> xml_attribute(const std::string& element, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto at = element.find(key);
  if (at == std::string::npos) return std::nullopt;
  const auto begin = at + key.size();
  const auto end = element.find('"', begin);
  if (end == std::string::npos) return std::nullopt;
  std::string out;
  for (std::size_t i = begin; i < end; ++i) {
    if (element[i] != '&') {
      out += element[i];
      continue;
    }
    static const std::pair<const char*, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    bool known = false;
    for (const auto& [text, c] : entities)
      if (element.compare(i, std::strlen(text), text) == 0) {
        out += c;
        i += std::strlen(text) - 1;
        known = true;
        break;
      }
    if (!known) return std::nullopt;
  }
  return out;
}

}  // namespace

PvdSeries::PvdSeries(std::filesystem::path pvd_file, double before) : path_(std::move(pvd_file)) {
  if (!std::filesystem::exists(path_)) return;
  const std::string xml = read_text_file(path_);
  if (xml.find("type=\"Collection\"") == std::string::npos)
    throw IoError(
        fmt::format("'{}' is not a ParaView collection (.pvd) to continue", path_.string()));
  for (std::size_t at = xml.find("<DataSet "); at != std::string::npos;
       at = xml.find("<DataSet ", at + 1)) {
    const auto close = xml.find("/>", at);
    if (close == std::string::npos) break;
    const std::string element = xml.substr(at, close - at);
    const auto t = xml_attribute(element, "timestep");
    const auto file = xml_attribute(element, "file");
    const auto part = xml_attribute(element, "part");
    double time = 0;
    int piece = 0;
    try {
      if (!t || !file) throw std::invalid_argument("missing attribute");
      time = std::stod(*t);
      if (part) piece = std::stoi(*part);
    } catch (const std::exception&) {
      throw IoError(fmt::format("'{}': unreadable data set '{}'", path_.string(), element));
    }
    if (time < before) entries_.push_back({time, *file, piece});
  }
}

void PvdSeries::add(double time, const std::string& relative_file, int part) {
  entries_.push_back({time, relative_file, part});
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += fmt::format("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"{}\">\n",
                     byte_order());
  xml += "  <Collection>\n";
  for (const Entry& e : entries_)
    xml += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"/>\n",
                       e.time, e.part, xml_escape(e.file));
  xml += "  </Collection>\n</VTKFile>\n";
  try {
    write_atomically(path_, [&](std::ostream& out) { out << xml; });
  } catch (...) {
    entries_.pop_back();  // keep memory and disk in step
    throw;
  }
}

}  // namespace gf::vtk
