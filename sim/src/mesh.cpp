// glTF loading through tinygltf. tinygltf parses the container; everything it
// hands back is validated here before use, because a malformed file must give
// a message naming the file and the fault, never an out-of-bounds read.
#include <sva/error.hpp>
#include <sva/sim/mesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <sva/base/finite.hpp>
#include <sva/io/json.hpp>

#include <sva/io/text_file.hpp>

namespace sva::sim {

namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": " + what);
}

// Bounds on what one file may make the loader build, checked before the memory is taken: a node graph may
// instance a mesh many times over (a node listing the same child a thousand times, 64 levels deep).
constexpr std::size_t kMaxVertices = std::size_t{1} << 22;  // 4 M vertices, 100 MB: 100x the largest asset
constexpr std::size_t kMaxNodeVisits = 1 << 16;
// External buffers (a .gltf naming a .bin) are read only when they are regular files of at most this size.
constexpr std::uintmax_t kMaxExternalBytes = std::uintmax_t{1} << 31;

// A validated window onto one accessor's bytes.
struct AccessorView {
  const unsigned char* data = nullptr;
  std::size_t count = 0;
  std::size_t stride = 0;
  int component_type = 0;
  int components = 0;
};

std::size_t component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    case TINYGLTF_COMPONENT_TYPE_DOUBLE:
      return 8;
    default:
      return 0;
  }
}

class Loader {
 public:
  Loader(const std::filesystem::path& file, const tinygltf::Model& model) : file_(file), m_(model) {}

  AccessorView view(int index, const std::string& what) const {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.accessors.size())
      fail(file_, what + ": accessor " + std::to_string(index) + " does not exist");
    const auto& a = m_.accessors[static_cast<std::size_t>(index)];
    std::string name = what + " (accessor " + std::to_string(index) + ")";
    if (a.sparse.isSparse) fail(file_, name + ": sparse accessors are not supported");
    if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= m_.bufferViews.size())
      fail(file_, name + ": missing or invalid bufferView " + std::to_string(a.bufferView));
    const auto& bv = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m_.buffers.size())
      fail(file_, name + ": bufferView refers to missing buffer " + std::to_string(bv.buffer));
    const auto& buf = m_.buffers[static_cast<std::size_t>(bv.buffer)];
    if (buf.data.empty()) fail(file_, name + ": buffer " + std::to_string(bv.buffer) + " is missing or empty");
    if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
      fail(file_, name + ": bufferView overruns its buffer (" + std::to_string(buf.data.size()) + " bytes)");
    AccessorView v;
    v.component_type = a.componentType;
    v.components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    std::size_t csize = component_size(a.componentType);
    if (v.components <= 0 || csize == 0) fail(file_, name + ": invalid type or component type");
    std::size_t elem = csize * static_cast<std::size_t>(v.components);
    v.stride = bv.byteStride ? bv.byteStride : elem;
    if (v.stride < elem) fail(file_, name + ": byteStride " + std::to_string(v.stride) + " is smaller than an element");
    v.count = a.count;
    if (v.count == 0) return v;
    if (a.byteOffset > bv.byteLength || (v.count - 1) > bv.byteLength / v.stride ||
        a.byteOffset + (v.count - 1) * v.stride + elem > bv.byteLength)
      fail(file_, name + ": " + std::to_string(v.count) + " elements overrun the bufferView (" +
                      std::to_string(bv.byteLength) + " bytes)");
    v.data = buf.data.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  std::vector<glm::dvec3> vec3s(int index, const std::string& what) const {
    AccessorView v = view(index, what);
    if (v.components != 3 || v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(file_, what + ": expected VEC3 of FLOAT");
    std::vector<glm::dvec3> out(v.count);
    for (std::size_t i = 0; i < v.count; ++i) {
      float f[3];
      std::memcpy(f, v.data + i * v.stride, sizeof f);
      out[i] = glm::dvec3(f[0], f[1], f[2]);
    }
    return out;
  }

  std::vector<std::uint32_t> indices(int index, std::size_t vertex_count) const {
    AccessorView v = view(index, "indices");
    if (v.components != 1) fail(file_, "indices: expected SCALAR");
    std::vector<std::uint32_t> out(v.count);
    for (std::size_t i = 0; i < v.count; ++i) {
      const unsigned char* p = v.data + i * v.stride;
      std::uint32_t x = 0;
      switch (v.component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          x = *p;
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          x = s;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          std::memcpy(&x, p, 4);
          break;
        default:
          fail(file_, "indices: component type must be an unsigned integer");
      }
      if (x >= vertex_count)
        fail(file_, "index " + std::to_string(x) + " at position " + std::to_string(i) + " is out of range (" +
                        std::to_string(vertex_count) + " vertices)");
      out[i] = x;
    }
    return out;
  }

  void add_primitive(const tinygltf::Primitive& p, const glm::dmat4& xf, const std::string& where, Mesh& mesh,
                     std::vector<char>& has_normal) const {
    if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        p.mode != TINYGLTF_MODE_TRIANGLE_FAN)
      return;  // points and lines carry no surface
    auto pos_it = p.attributes.find("POSITION");
    if (pos_it == p.attributes.end()) fail(file_, where + ": primitive has no POSITION attribute");
    std::vector<glm::dvec3> pos = vec3s(pos_it->second, where + " POSITION");
    std::vector<glm::dvec3> nrm;
    if (auto n_it = p.attributes.find("NORMAL"); n_it != p.attributes.end()) {
      nrm = vec3s(n_it->second, where + " NORMAL");
      if (nrm.size() != pos.size()) fail(file_, where + ": NORMAL and POSITION counts differ");
    }
    std::vector<std::uint32_t> idx;
    if (p.indices >= 0) {
      idx = indices(p.indices, pos.size());
    } else {
      idx.resize(pos.size());
      for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<std::uint32_t>(i);
    }
    const glm::dmat3 lin(xf);
    const glm::dmat3 nxf = glm::transpose(glm::inverse(lin));
    const bool flip = glm::determinant(lin) < 0.0;
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    if (pos.size() > kMaxVertices - base)
      fail(file_, where + ": the node graph instances more than " + std::to_string(kMaxVertices) + " vertices");
    for (std::size_t i = 0; i < pos.size(); ++i) {
      glm::dvec3 w = glm::dvec3(xf * glm::dvec4(pos[i], 1.0));
      if (!finite(pos[i]) || !finite(w))
        fail(file_, where + ": vertex " + std::to_string(i) + " has a non-finite (NaN or infinite) coordinate");
      mesh.positions.emplace_back(w);
      glm::dvec3 n(0.0);
      bool ok = false;
      if (!nrm.empty() && finite(nrm[i])) {
        n = nxf * nrm[i];
        double len = glm::length(n);
        ok = len > 1e-12 && std::isfinite(len);
        if (ok) n /= len;
      }
      mesh.normals.emplace_back(ok ? n : glm::dvec3(0.0));
      has_normal.push_back(ok);
    }
    auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      if (a == b || b == c || a == c) return;
      if (flip) std::swap(b, c);
      mesh.triangles.emplace_back(base + a, base + b, base + c);
    };
    if (p.mode == TINYGLTF_MODE_TRIANGLES) {
      if (idx.size() % 3 != 0)
        fail(file_, where + ": triangle list length " + std::to_string(idx.size()) + " is not a multiple of 3");
      for (std::size_t i = 0; i + 2 < idx.size(); i += 3) tri(idx[i], idx[i + 1], idx[i + 2]);
    } else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
        if (i % 2 == 0)
          tri(idx[i], idx[i + 1], idx[i + 2]);
        else
          tri(idx[i + 1], idx[i], idx[i + 2]);
      }
    } else {
      for (std::size_t i = 1; i + 1 < idx.size(); ++i) tri(idx[0], idx[i], idx[i + 1]);
    }
  }

  glm::dmat4 local_transform(const tinygltf::Node& n, const std::string& where) const {
    if (n.matrix.size() == 16) {
      glm::dmat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[static_cast<std::size_t>(4 * c + r)];
      return m;
    }
    if (!n.matrix.empty()) fail(file_, where + ": matrix must have 16 numbers");
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (n.translation.size() == 3)
      t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
    else if (!n.translation.empty())
      fail(file_, where + ": translation must have 3 numbers");
    if (n.rotation.size() == 4) {
      glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      double len = glm::length(q);
      if (!(len > 1e-12) || !std::isfinite(len)) fail(file_, where + ": rotation quaternion has zero length");
      r = glm::dmat4(glm::mat3_cast(q / len));
    } else if (!n.rotation.empty()) {
      fail(file_, where + ": rotation must have 4 numbers");
    }
    if (n.scale.size() == 3)
      s = glm::dmat4(
          glm::dmat3(glm::dvec3(n.scale[0], 0, 0), glm::dvec3(0, n.scale[1], 0), glm::dvec3(0, 0, n.scale[2])));
    else if (!n.scale.empty())
      fail(file_, where + ": scale must have 3 numbers");
    return t * r * s;
  }

  void visit(int node, const glm::dmat4& parent, int depth, Mesh& mesh, std::vector<char>& has_normal) const {
    if (node < 0 || static_cast<std::size_t>(node) >= m_.nodes.size())
      fail(file_, "node " + std::to_string(node) + " does not exist");
    if (depth > 64) fail(file_, "node hierarchy is deeper than 64 levels (a cycle?)");
    if (++visits_ > kMaxNodeVisits)
      fail(file_, "the node graph visits more than " + std::to_string(kMaxNodeVisits) + " nodes (shared children)");
    const auto& n = m_.nodes[static_cast<std::size_t>(node)];
    std::string where = "node " + std::to_string(node);
    glm::dmat4 xf = parent * local_transform(n, where);
    for (int c = 0; c < 4; ++c)
      if (!finite(glm::dvec3(xf[c])) || !std::isfinite(xf[c][3])) fail(file_, where + ": non-finite transform");
    if (n.mesh >= 0) {
      if (static_cast<std::size_t>(n.mesh) >= m_.meshes.size())
        fail(file_, where + ": mesh " + std::to_string(n.mesh) + " does not exist");
      const auto& me = m_.meshes[static_cast<std::size_t>(n.mesh)];
      for (std::size_t p = 0; p < me.primitives.size(); ++p)
        add_primitive(me.primitives[p], xf, "mesh " + std::to_string(n.mesh) + " primitive " + std::to_string(p), mesh,
                      has_normal);
    }
    for (int child : n.children) visit(child, xf, depth + 1, mesh, has_normal);
  }

 private:
  const std::filesystem::path& file_;
  const tinygltf::Model& m_;
  mutable std::size_t visits_ = 0;
};

// tinygltf's file reader, bounded: a buffer URI naming a device, a directory or a huge file (/dev/zero,
// /proc/kcore) is refused instead of being read or allocated for.
bool read_external_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec || !std::filesystem::is_regular_file(path, ec) || size == 0 || size > kMaxExternalBytes) {
    if (err) *err += "external file " + path + " is not a regular file of 1 byte to 2 GiB\n";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
    if (err) *err += "cannot read external file " + path + "\n";
    return false;
  }
  return true;
}

// The JSON text of a .gltf, or of a .glb's first chunk (empty when the header is malformed: tinygltf reports it).
std::string_view gltf_json(const std::vector<unsigned char>& bytes, bool binary) {
  const char* text = reinterpret_cast<const char*>(bytes.data());
  if (!binary) return {text, bytes.size()};
  if (bytes.size() < 20) return {};
  std::uint32_t length;
  std::memcpy(&length, bytes.data() + 12, 4);
  return {text + 20, std::min<std::size_t>(length, bytes.size() - 20)};
}

void compute_missing_normals(Mesh& mesh, const std::vector<char>& has_normal) {
  std::vector<glm::dvec3> acc(mesh.positions.size(), glm::dvec3(0.0));
  for (const auto& t : mesh.triangles) {
    glm::dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    glm::dvec3 n = glm::cross(b - a, c - a);  // length = 2 * area: area weighting
    acc[t.x] += n;
    acc[t.y] += n;
    acc[t.z] += n;
  }
  for (std::size_t i = 0; i < acc.size(); ++i) {
    if (has_normal[i]) continue;
    double len = glm::length(acc[i]);
    mesh.normals[i] = len > 0 ? glm::vec3(acc[i] / len) : glm::vec3(0, 0, 1);
  }
}

std::vector<unsigned char> read_file(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) fail(file, "no such file");
  if (std::filesystem::is_directory(file, ec)) fail(file, "is a directory, not a glTF file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open for reading");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) fail(file, "empty file (expected glTF 2.0 .gltf or .glb)");
  return bytes;
}

}  // namespace

double Mesh::area() const {
  double a = 0;
  for (const auto& t : triangles) {
    glm::dvec3 p(positions[t.x]), q(positions[t.y]), r(positions[t.z]);
    a += 0.5 * glm::length(glm::cross(q - p, r - p));
  }
  return a;
}

void Mesh::update_bounds() {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 p(positions[t[k]]);
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  if (triangles.empty()) lo = hi = glm::dvec3(0.0);
  bounds_min = lo;
  bounds_max = hi;
}

Mesh load_mesh(const std::filesystem::path& file) {
  std::vector<unsigned char> bytes = read_file(file);
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    std::size_t i = 0;
    while (i < bytes.size() && std::isspace(bytes[i])) ++i;
    if (i == bytes.size() || bytes[i] != '{')
      fail(file, "not a glTF file (neither the binary 'glTF' magic nor a JSON object)");
  }
  if (io::json_depth(gltf_json(bytes, binary)) > io::kMaxJsonDepth) fail(file, io::json_too_deep_message());
  tinygltf::TinyGLTF gltf;
  gltf.SetFsCallbacks(
      {&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_external_file, &tinygltf::WriteWholeFile, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  // Images are irrelevant to touch; skip decoding them (and their failures).
  gltf.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                         void*) { return true; },
                      nullptr);
  std::string base_dir = file.has_parent_path() ? file.parent_path().string() : std::string(".");
  bool ok = false;
  try {
    if (binary)
      ok = gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
    else
      ok = gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                    static_cast<unsigned>(bytes.size()), base_dir);
  } catch (const std::exception& e) {
    fail(file, std::string("invalid glTF: ") + e.what());
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    for (auto& ch : err)
      if (ch == '\n') ch = ';';
    fail(file, "invalid glTF: " + (err.empty() ? std::string("tinygltf could not parse it") : err));
  }
  for (std::size_t b = 0; b < model.buffers.size(); ++b)
    if (model.buffers[b].data.empty() && model.buffers[b].uri.size())
      fail(file, "buffer " + std::to_string(b) + " (\"" + model.buffers[b].uri + "\") is missing or empty");

  Loader loader(file, model);
  Mesh mesh;
  std::vector<char> has_normal;
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    int s = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (static_cast<std::size_t>(s) >= model.scenes.size())
      fail(file, "default scene " + std::to_string(s) + " does not exist");
    roots = model.scenes[static_cast<std::size_t>(s)].nodes;
  } else {
    std::vector<char> is_child(model.nodes.size(), 0);
    for (const auto& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<std::size_t>(c) < is_child.size()) is_child[static_cast<std::size_t>(c)] = 1;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
  }
  for (int r : roots) loader.visit(r, glm::dmat4(1.0), 0, mesh, has_normal);
  if (mesh.triangles.empty()) fail(file, "contains no triangles (empty mesh or only points and lines)");
  compute_missing_normals(mesh, has_normal);
  mesh.update_bounds();
  double area = mesh.area();
  if (!(area > 0.0) || !std::isfinite(area)) fail(file, "mesh has zero (or non-finite) surface area");
  if (!(glm::length(mesh.extent()) > 0.0)) fail(file, "mesh has zero extent");
  return mesh;
}

void fit_mesh(Mesh& mesh, const SceneObject& object) {
  glm::dvec3 ext = mesh.extent();
  double largest = std::max({ext.x, ext.y, ext.z});
  double scale = (object.size_mm > 0 && largest > 0) ? object.size_mm / largest : 1.0;
  glm::dvec3 shift = object.center ? 0.5 * (mesh.bounds_min + mesh.bounds_max) : glm::dvec3(0.0);
  for (auto& p : mesh.positions) p = glm::vec3((glm::dvec3(p) - shift) * scale);
  mesh.update_bounds();
}

Mesh load_object_mesh(const SceneObject& object) {
  Mesh m = load_mesh(object.mesh);
  fit_mesh(m, object);
  return m;
}

std::vector<ObjectSurface> object_surfaces(const Scene& scene) {
  std::vector<ObjectSurface> out;
  for (const SceneObject& o : scene.objects) {
    Mesh m;
    try {
      m = load_object_mesh(o);
    } catch (const Error& e) {
      throw Error("the surface of object \"" + o.name + "\": " + e.what());
    }
    ObjectSurface s;
    s.positions = std::move(m.positions);
    s.triangles = std::move(m.triangles);
    out.push_back(std::move(s));
  }
  return out;
}

void save_glb(const Mesh& mesh, const std::filesystem::path& file, bool with_normals) {
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  auto append = [&](const void* data, std::size_t bytes) {
    std::size_t offset = buffer.data.size();
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.data.insert(buffer.data.end(), p, p + bytes);
    while (buffer.data.size() % 4) buffer.data.push_back(0);
    return offset;
  };
  auto add_view = [&](std::size_t offset, std::size_t bytes, int target) {
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = offset;
    v.byteLength = bytes;
    v.target = target;
    model.bufferViews.push_back(v);
    return static_cast<int>(model.bufferViews.size() - 1);
  };
  Mesh m = mesh;
  m.update_bounds();
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  // One float VEC3 vertex attribute: its buffer view and accessor.
  auto add_vec3_attribute = [&](const std::vector<glm::vec3>& v, const char* name, bool with_bounds) {
    const std::size_t bytes = v.size() * sizeof(glm::vec3);
    tinygltf::Accessor a;
    a.bufferView = add_view(append(v.data(), bytes), bytes, TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = TINYGLTF_TYPE_VEC3;
    a.count = v.size();
    if (with_bounds) {
      a.minValues = {m.bounds_min.x, m.bounds_min.y, m.bounds_min.z};
      a.maxValues = {m.bounds_max.x, m.bounds_max.y, m.bounds_max.z};
    }
    model.accessors.push_back(a);
    prim.attributes[name] = static_cast<int>(model.accessors.size() - 1);
  };
  add_vec3_attribute(m.positions, "POSITION", true);
  if (with_normals && m.normals.size() == m.positions.size()) add_vec3_attribute(m.normals, "NORMAL", false);
  {
    std::size_t bytes = m.triangles.size() * sizeof(glm::uvec3);
    tinygltf::Accessor a;
    a.bufferView = add_view(append(m.triangles.data(), bytes), bytes, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = m.triangles.size() * 3;
    model.accessors.push_back(a);
    prim.indices = static_cast<int>(model.accessors.size() - 1);
  }
  model.buffers.push_back(buffer);
  tinygltf::Mesh gm;
  gm.name = file.stem().string();
  gm.primitives.push_back(prim);
  model.meshes.push_back(gm);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = gm.name;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.asset.version = "2.0";
  model.asset.generator = "sva_make_assets";

  std::ostringstream out;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, out, false, true)) throw Error(file.string() + ": cannot encode glTF");
  io::write_text_file(file, out.str());
}

}  // namespace sva::sim
