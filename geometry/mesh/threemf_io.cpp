// Reading 3MF files; see threemf_io.h. The archive through libzip, the XML through pugixml.
#include "geometry/mesh/threemf_io.h"

#include <zip.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

#include <fmt/core.h>
#include <pugixml.hpp>

#include "geometry/core/error.h"

namespace geometry {
namespace {

[[noreturn]] void fail(std::string_view name, const std::string& problem) {
  throw InputError(fmt::format("{}: {}", name, problem));
}

// An affine map of 3MF's: row i gives coordinate i from x, y, z and 1.
struct Affine {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  Vec3 apply(const Vec3& p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  // This map after `inner`.
  Affine after(const Affine& inner) const {
    Affine out;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) {
        double v = j == 3 ? m[i][3] : 0;
        for (int k = 0; k < 3; ++k) v += m[i][k] * inner.m[k][j];
        out.m[i][j] = v;
      }
    }
    return out;
  }
  double determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
};

// A number as 3MF writes one (ST_Number: an optional sign, digits, exponent), or nullopt.
std::optional<double> number(const char* text) {
  while (*text == ' ' || *text == '\t' || *text == '\n' || *text == '\r') ++text;
  if (*text == '+') ++text;
  const char* end = text + std::strlen(text);
  while (end > text && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\n' || end[-1] == '\r')) --end;
  double value = 0;
  const auto [stop, error] = std::from_chars(text, end, value);
  if (error != std::errc() || stop != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

// The element's or attribute's name without its namespace prefix.
std::string_view local_name(const char* name) {
  const std::string_view n = name;
  const std::size_t colon = n.find(':');
  return colon == std::string_view::npos ? n : n.substr(colon + 1);
}

pugi::xml_node child(const pugi::xml_node& node, std::string_view name) {
  for (pugi::xml_node c = node.first_child(); c; c = c.next_sibling()) {
    if (c.type() == pugi::node_element && local_name(c.name()) == name) return c;
  }
  return {};
}

pugi::xml_attribute attribute(const pugi::xml_node& node, std::string_view name) {
  for (pugi::xml_attribute a = node.first_attribute(); a; a = a.next_attribute()) {
    if (local_name(a.name()) == name) return a;
  }
  return {};
}

double unit_to_mm(std::string_view unit, std::string_view where) {
  if (unit == "micron") return 0.001;
  if (unit == "millimeter") return 1;
  if (unit == "centimeter") return 10;
  if (unit == "inch") return 25.4;
  if (unit == "foot") return 304.8;
  if (unit == "meter") return 1000;
  fail(where, fmt::format("unknown unit '{}' (3MF has micron, millimeter, centimeter, inch, "
                          "foot, meter)", unit));
}

// A part's bytes in memory from malloc, which pugixml frees once a document owns them
// (load_buffer_inplace_own: parsed where they are, neither copied nor zeroed first).
struct PartBytes {
  char* data = nullptr;
  std::size_t size = 0;
  PartBytes() = default;
  PartBytes(const PartBytes&) = delete;
  PartBytes& operator=(const PartBytes&) = delete;
  PartBytes(PartBytes&& other) noexcept : data(std::exchange(other.data, nullptr)), size(other.size) {}
  ~PartBytes() { std::free(data); }
};

// The zip archive, read in place from the caller's bytes.
class Archive {
 public:
  Archive(std::string_view bytes, std::string_view name) : name_(name) {
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* source = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
    if (source) zip_ = zip_open_from_source(source, ZIP_RDONLY, &error);
    if (!zip_) {
      const std::string why = zip_error_strerror(&error);
      if (source) zip_source_free(source);
      zip_error_fini(&error);
      fail(name, fmt::format("not a 3MF file: the zip archive cannot be read ({})", why));
    }
    zip_error_fini(&error);
  }
  ~Archive() {
    if (zip_) zip_discard(zip_);
  }
  Archive(const Archive&) = delete;
  Archive& operator=(const Archive&) = delete;

  bool has(const std::string& part) const { return zip_name_locate(zip_, part.c_str(), 0) >= 0; }

  // The part's bytes; `part` without a leading '/'.
  PartBytes read(const std::string& part) const {
    const zip_int64_t index = zip_name_locate(zip_, part.c_str(), 0);
    if (index < 0) fail(name_, fmt::format("the archive has no part '/{}'", part));
    zip_stat_t stat;
    zip_stat_init(&stat);
    if (zip_stat_index(zip_, index, 0, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE)) {
      fail(name_, fmt::format("/{}: cannot read its size in the archive", part));
    }
    zip_file_t* file = zip_fopen_index(zip_, index, 0);
    if (!file) fail(name_, fmt::format("/{}: cannot be opened ({})", part, zip_strerror(zip_)));
    PartBytes bytes;
    bytes.size = stat.size;
    bytes.data = static_cast<char*>(std::malloc(std::max<std::size_t>(bytes.size, 1)));
    if (!bytes.data) throw std::bad_alloc();
    const zip_int64_t got = zip_fread(file, bytes.data, bytes.size);
    const std::string why = got < 0 ? zip_file_strerror(file) : "";
    zip_fclose(file);
    if (got < 0 || static_cast<zip_uint64_t>(got) != stat.size) {
      fail(name_, fmt::format("/{}: the archive is damaged{}", part, why.empty() ? "" : " (" + why + ")"));
    }
    return bytes;
  }

 private:
  zip_t* zip_ = nullptr;
  std::string name_;
};

// Elements and attributes only: no text, escapes or line-end conversions, which nothing read
// here needs (numbers, ids, names).
pugi::xml_document parse_xml(PartBytes bytes, std::string_view name, const std::string& part) {
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer_inplace_own(bytes.data, bytes.size, pugi::parse_minimal);
  bytes.data = nullptr;  // the document's now
  if (!parsed) {
    fail(name, fmt::format("/{}: not well-formed XML at byte {}: {}", part, parsed.offset,
                           parsed.description()));
  }
  return doc;
}

// PrusaSlicer's volumes of an object: the triangles firstid..lastid of its mesh, and what
// they are (ModelPart, ParameterModifier, SupportBlocker, SupportEnforcer, NegativeVolume).
struct Volume {
  std::size_t first = 0, last = 0;
  std::string type = "ModelPart";
};

class Reader {
 public:
  Reader(const Archive& archive, std::string_view name) : archive_(archive), name_(name) {}

  ThreeMfModel read() {
    const std::string root = root_part();
    read_prusaslicer_volumes();
    Part& model = part(root);
    const pugi::xml_node model_node = child(model.doc, "model");
    const pugi::xml_attribute unit = attribute(model_node, "unit");
    ThreeMfModel out;
    out.unit = unit ? unit.value() : "millimeter";
    Affine scale;
    const double mm = unit_to_mm(out.unit, where(root));
    for (int i = 0; i < 3; ++i) scale.m[i][i] = mm;
    const pugi::xml_node build = child(model_node, "build");
    if (!build) fail(name_, fmt::format("/{}: no <build>: nothing to print", root));
    for (pugi::xml_node item = build.first_child(); item; item = item.next_sibling()) {
      if (item.type() != pugi::node_element || local_name(item.name()) != "item") continue;
      const pugi::xml_attribute printable = attribute(item, "printable");
      if (printable && std::string_view(printable.value()) == "0") continue;
      const pugi::xml_attribute path = attribute(item, "path");
      const std::string item_part = path ? part_name(path.value()) : root;
      const Affine placed = scale.after(transform(item, root));
      emit(item_part, object_id(item, root), placed, item_part == root, 0, out.triangles);
      ++out.items;
    }
    if (out.triangles.empty()) {
      fail(name_, fmt::format("/{}: the build places no triangles: nothing to print", root));
    }
    return out;
  }

 private:
  struct Part {
    pugi::xml_document doc;
    std::unordered_map<std::string, pugi::xml_node> objects;  // by id
  };

  std::string where(const std::string& part) const { return fmt::format("{}: /{}", name_, part); }

  static std::string part_name(std::string_view path) {
    while (!path.empty() && path.front() == '/') path.remove_prefix(1);
    return std::string(path);
  }

  // The 3D model part the package relationships name (3D/3dmodel.model by convention).
  std::string root_part() const {
    constexpr std::string_view kModelType = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";
    if (archive_.has("_rels/.rels")) {
      const pugi::xml_document rels = parse_xml(archive_.read("_rels/.rels"), name_, "_rels/.rels");
      for (pugi::xml_node r = child(rels, "Relationships").first_child(); r; r = r.next_sibling()) {
        if (std::string_view(attribute(r, "Type").value()) == kModelType) {
          return part_name(attribute(r, "Target").value());
        }
      }
    }
    if (archive_.has("3D/3dmodel.model")) return "3D/3dmodel.model";
    fail(name_, "not a 3MF file: the archive has no 3D model part (/3D/3dmodel.model)");
  }

  void read_prusaslicer_volumes() {
    const std::string config = "Metadata/Slic3r_PE_model.config";
    if (!archive_.has(config)) return;
    const pugi::xml_document doc = parse_xml(archive_.read(config), name_, config);
    for (pugi::xml_node object : child(doc, "config").children("object")) {
      std::vector<Volume>& volumes = volumes_[object.attribute("id").value()];
      for (pugi::xml_node v : object.children("volume")) {
        Volume volume;
        volume.first = v.attribute("firstid").as_ullong();
        volume.last = v.attribute("lastid").as_ullong();
        for (pugi::xml_node meta : v.children("metadata")) {
          if (std::string_view(meta.attribute("key").value()) == "volume_type") {
            volume.type = meta.attribute("value").value();
          }
        }
        volumes.push_back(volume);
      }
    }
  }

  Part& part(const std::string& path) {
    auto found = parts_.find(path);
    if (found != parts_.end()) return *found->second;
    auto loaded = std::make_unique<Part>();
    loaded->doc = parse_xml(archive_.read(path), name_, path);
    const pugi::xml_node model = child(loaded->doc, "model");
    if (!model) fail(where(path), "no <model> element: not a 3D model part");
    for (pugi::xml_node object : child(model, "resources").children()) {
      if (local_name(object.name()) == "object") {
        loaded->objects[attribute(object, "id").value()] = object;
      }
    }
    return *parts_.emplace(path, std::move(loaded)).first->second;
  }

  std::string object_id(const pugi::xml_node& node, const std::string& part_path) const {
    const pugi::xml_attribute id = attribute(node, "objectid");
    if (!id) fail(where(part_path), fmt::format("a <{}> without an objectid", node.name()));
    return id.value();
  }

  Affine transform(const pugi::xml_node& node, const std::string& part_path) const {
    Affine a;
    const pugi::xml_attribute t = attribute(node, "transform");
    if (!t) return a;
    std::string_view text = t.value();
    double v[12];
    int count = 0;
    while (!text.empty()) {
      const std::size_t start = text.find_first_not_of(" \t\r\n");
      if (start == std::string_view::npos) break;
      text.remove_prefix(start);
      const std::size_t stop = std::min(text.find_first_of(" \t\r\n"), text.size());
      const auto x = count < 12 ? number(std::string(text.substr(0, stop)).c_str()) : std::nullopt;
      if (!x) count = 13;
      if (count >= 12) break;
      v[count++] = *x;
      text.remove_prefix(stop);
    }
    if (count != 12) {
      fail(where(part_path), fmt::format("transform \"{}\" is not 12 numbers", t.value()));
    }
    // 3MF's row vector times a 4x3 matrix: x' = x m00 + y m10 + z m20 + m30, ...
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) a.m[i][j] = v[3 * j + i];
    }
    return a;
  }

  void emit(const std::string& part_path, const std::string& id, const Affine& placed,
            bool in_root, int depth, std::vector<Triangle>& out) {
    if (depth > 32) {
      fail(where(part_path), fmt::format("object {} nests components more than 32 deep (a cycle?)", id));
    }
    Part& p = part(part_path);
    const auto found = p.objects.find(id);
    if (found == p.objects.end()) fail(where(part_path), fmt::format("no object with id {}", id));
    const pugi::xml_node object = found->second;
    const pugi::xml_attribute type = attribute(object, "type");
    if (type && std::string_view(type.value()) != "model") return;
    if (const pugi::xml_node mesh = child(object, "mesh")) {
      emit_mesh(mesh, part_path, id, placed, in_root, out);
    }
    if (const pugi::xml_node components = child(object, "components")) {
      for (pugi::xml_node c = components.first_child(); c; c = c.next_sibling()) {
        if (c.type() != pugi::node_element || local_name(c.name()) != "component") continue;
        const pugi::xml_attribute path = attribute(c, "path");
        const std::string target = path ? part_name(path.value()) : part_path;
        emit(target, object_id(c, part_path), placed.after(transform(c, part_path)),
             in_root && target == part_path, depth + 1, out);
      }
    }
  }

  void emit_mesh(const pugi::xml_node& mesh, const std::string& part_path, const std::string& id,
                 const Affine& placed, bool in_root, std::vector<Triangle>& out) {
    std::vector<Vec3> vertices;
    for (pugi::xml_node v = child(mesh, "vertices").first_child(); v; v = v.next_sibling()) {
      if (v.type() != pugi::node_element) continue;
      // The attributes in one pass (a mesh has millions): x, y and z by their one letter.
      std::optional<double> c[3];
      for (pugi::xml_attribute a = v.first_attribute(); a; a = a.next_attribute()) {
        const char* n = a.name();
        if (n[0] >= 'x' && n[0] <= 'z' && n[1] == '\0') c[n[0] - 'x'] = number(a.value());
      }
      if (!c[0] || !c[1] || !c[2]) {
        fail(where(part_path), fmt::format("object {}, vertex {}: x, y and z must be numbers",
                                           id, vertices.size()));
      }
      vertices.push_back(placed.apply({*c[0], *c[1], *c[2]}));
    }
    // PrusaSlicer's modifiers, blockers and enforcers share the mesh with the parts.
    const std::vector<Volume>* volumes = nullptr;
    if (in_root) {
      const auto found = volumes_.find(id);
      if (found != volumes_.end()) volumes = &found->second;
    }
    if (volumes) {
      for (const Volume& v : *volumes) {
        if (v.type == "NegativeVolume") {
          fail(name_, fmt::format("object {} has a negative volume (a shape PrusaSlicer cuts out "
                                  "of the part), which mahost cannot cut; apply it in "
                                  "PrusaSlicer or export the parts as STL", id));
        }
      }
    }
    const bool mirrored = placed.determinant() < 0;
    std::size_t index = 0;
    for (pugi::xml_node t = child(mesh, "triangles").first_child(); t; t = t.next_sibling()) {
      if (t.type() != pugi::node_element) continue;
      const std::size_t triangle = index++;
      if (volumes && !part_triangle(*volumes, triangle)) continue;
      // v1, v2, v3 in one pass over the attributes (p1, pid, ... are skipped).
      const char* corners[3] = {nullptr, nullptr, nullptr};
      for (pugi::xml_attribute a = t.first_attribute(); a; a = a.next_attribute()) {
        const char* n = a.name();
        if (n[0] == 'v' && n[1] >= '1' && n[1] <= '3' && n[2] == '\0') corners[n[1] - '1'] = a.value();
      }
      Triangle tri;
      for (int k = 0; k < 3; ++k) {
        const char* text = corners[k] ? corners[k] : "";
        std::size_t v = 0;
        const char* end = text + std::strlen(text);
        const auto [stop, error] = std::from_chars(text, end, v);
        if (error != std::errc() || stop != end || v >= vertices.size()) {
          fail(where(part_path), fmt::format("object {}, triangle {}: v{}=\"{}\" is not a vertex "
                                             "(the mesh has {})", id, triangle, k + 1, text,
                                             vertices.size()));
        }
        tri.v[k] = vertices[v];
      }
      if (mirrored) std::swap(tri.v[1], tri.v[2]);
      out.push_back(tri);
    }
  }

  static bool part_triangle(const std::vector<Volume>& volumes, std::size_t triangle) {
    for (const Volume& v : volumes) {
      if (triangle >= v.first && triangle <= v.last) return v.type == "ModelPart";
    }
    return true;
  }

  const Archive& archive_;
  std::string name_;
  std::map<std::string, std::unique_ptr<Part>> parts_;
  std::unordered_map<std::string, std::vector<Volume>> volumes_;  // PrusaSlicer's, by object id
};

}  // namespace

bool looks_like_zip(std::string_view bytes) { return bytes.substr(0, 4) == std::string_view("PK\3\4", 4); }

ThreeMfModel read_3mf_bytes(std::string_view bytes, std::string_view name) {
  if (bytes.empty()) fail(name, "empty file (0 bytes): not a 3MF model");
  const Archive archive(bytes, name);
  return Reader(archive, name).read();
}

}  // namespace geometry
