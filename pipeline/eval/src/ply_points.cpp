#include "vifusion/eval/ply_points.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::eval {
namespace {

struct Property {
  std::string name;
  std::string type;
  std::size_t bytes = 0;
};

std::size_t typeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

double readBinary(const char* data, const std::string& type, const std::string& file) {
  // Little-endian host assumed for binary_little_endian files (x86-64 and aarch64 Linux are).
  if (type == "float" || type == "float32") {
    float value;
    std::memcpy(&value, data, 4);
    return value;
  }
  if (type == "double" || type == "float64") {
    double value;
    std::memcpy(&value, data, 8);
    return value;
  }
  throw Error(file + ": position property of type '" + type + "' (expected float or double)");
}

}  // namespace

std::vector<Eigen::Vector3d> readPlyPositions(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot be read");
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw Error(name + ": not a PLY file (no 'ply' magic)");

  bool binary = false;
  std::size_t vertex_count = 0;
  bool in_vertex = false;
  bool vertex_first = true;  // the vertex element must come first for a sequential read
  bool seen_element = false;
  bool header_ended = false;
  std::vector<Property> properties;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format == "binary_little_endian") {
        binary = true;
      } else if (format != "ascii") {
        throw Error(name + ": PLY format '" + format + "' is not supported (ascii or binary_little_endian)");
      }
    } else if (keyword == "element") {
      std::string element;
      std::size_t count = 0;
      words >> element >> count;
      in_vertex = element == "vertex";
      if (in_vertex) {
        vertex_count = count;
        vertex_first = !seen_element;
      }
      seen_element = true;
    } else if (keyword == "property" && in_vertex) {
      Property property;
      words >> property.type;
      if (property.type == "list") throw Error(name + ": list properties on vertices are not supported");
      words >> property.name;
      property.bytes = typeBytes(property.type);
      if (property.bytes == 0) throw Error(name + ": unknown PLY property type '" + property.type + "'");
      properties.push_back(property);
    } else if (keyword == "end_header") {
      header_ended = true;
      break;
    }
  }
  if (!header_ended) throw Error(name + ": no end_header line (truncated or not a PLY header)");
  if (!vertex_first) throw Error(name + ": the vertex element must be the first element");
  int index[3] = {-1, -1, -1};
  std::size_t offset[3] = {0, 0, 0};
  std::size_t stride = 0;
  for (std::size_t i = 0; i < properties.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      if (properties[i].name == std::string(1, static_cast<char>('x' + axis))) {
        index[axis] = static_cast<int>(i);
        offset[axis] = stride;
      }
    }
    stride += properties[i].bytes;
  }
  if (index[0] < 0 || index[1] < 0 || index[2] < 0) throw Error(name + ": vertices have no x, y and z properties");

  // The count is checked against the bytes left before anything is reserved, so a corrupt header cannot ask
  // for gigabytes: a binary vertex takes `stride` bytes, an ASCII one at least a digit and a separator per
  // property.
  const std::streamoff header_end = in.tellg();
  in.seekg(0, std::ios::end);
  const auto bytes_left = static_cast<std::size_t>(std::max<std::streamoff>(0, in.tellg() - header_end));
  in.seekg(header_end);
  const std::size_t min_vertex_bytes = binary ? stride : 2 * properties.size();
  if (vertex_count > bytes_left / min_vertex_bytes) {
    throw Error(name + ": the header promises " + std::to_string(vertex_count) + " vertices, but only " +
                std::to_string(bytes_left) + " bytes follow it (truncated file or corrupt vertex count)");
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(vertex_count);
  const auto keep = [&](std::size_t v, const Eigen::Vector3d& p) {
    if (!p.allFinite()) throw Error(name + ": vertex " + std::to_string(v) + " has a position that is not finite");
    points.push_back(p);
  };
  if (binary) {
    std::vector<char> record(stride);
    for (std::size_t v = 0; v < vertex_count; ++v) {
      if (!in.read(record.data(), static_cast<std::streamsize>(stride))) {
        throw Error(name + ": truncated after " + std::to_string(v) + " of " + std::to_string(vertex_count) +
                    " vertices");
      }
      Eigen::Vector3d p;
      for (int axis = 0; axis < 3; ++axis) {
        p[axis] = readBinary(record.data() + offset[axis], properties[index[axis]].type, name);
      }
      keep(v, p);
    }
  } else {
    for (std::size_t v = 0; v < vertex_count; ++v) {
      if (!std::getline(in, line)) {
        throw Error(name + ": truncated after " + std::to_string(v) + " of " + std::to_string(vertex_count) +
                    " vertices");
      }
      std::istringstream values(line);
      std::vector<double> fields(properties.size());
      for (double& field : fields) {
        if (!(values >> field)) throw Error(name + ": vertex " + std::to_string(v) + " has too few values");
      }
      keep(v, Eigen::Vector3d(fields[index[0]], fields[index[1]], fields[index[2]]));
    }
  }
  return points;
}

}  // namespace vifusion::eval
