#pragma once
// Writes small glTF files for the simulator tests: a .gltf JSON beside a .bin
// buffer, so that tests can also break them on purpose (edit the JSON, remove
// the buffer). Meshes are given as float positions and uint32 indices.
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace sva::test {

struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
};

// Returns the glTF JSON (one mesh, one primitive, one node) and writes the
// buffer as `bin`. The caller may edit the JSON before write_json().
inline nlohmann::json gltf_json(const TestMesh& m, const std::filesystem::path& bin, int mode = 4) {
  std::vector<unsigned char> bytes(m.positions.size() * 12 + m.indices.size() * 4);
  // memcpy from an empty vector's null data() is undefined, even for 0 bytes.
  if (!m.positions.empty()) std::memcpy(bytes.data(), m.positions.data(), m.positions.size() * 12);
  if (!m.indices.empty()) std::memcpy(bytes.data() + m.positions.size() * 12, m.indices.data(), m.indices.size() * 4);
  std::ofstream(bin, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (auto p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  using nlohmann::json;
  json j;
  j["asset"] = {{"version", "2.0"}};
  j["buffers"] = json::array({{{"uri", bin.filename().string()}, {"byteLength", bytes.size()}}});
  j["bufferViews"] =
      json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", m.positions.size() * 12}},
                   {{"buffer", 0}, {"byteOffset", m.positions.size() * 12}, {"byteLength", m.indices.size() * 4}}});
  j["accessors"] =
      json::array({{{"bufferView", 0},
                    {"componentType", 5126},
                    {"count", m.positions.size()},
                    {"type", "VEC3"},
                    {"min", {lo.x, lo.y, lo.z}},
                    {"max", {hi.x, hi.y, hi.z}}},
                   {{"bufferView", 1}, {"componentType", 5125}, {"count", m.indices.size()}, {"type", "SCALAR"}}});
  j["meshes"] = json::array(
      {{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", mode}}})}}});
  j["nodes"] = json::array({{{"mesh", 0}}});
  j["scenes"] = json::array({{{"nodes", {0}}}});
  j["scene"] = 0;
  return j;
}

inline void write_json(const nlohmann::json& j, const std::filesystem::path& file) { std::ofstream(file) << j.dump(1); }

inline std::filesystem::path write_gltf(const TestMesh& m, const std::filesystem::path& file, int mode = 4) {
  auto bin = file;
  bin.replace_extension(".bin");
  write_json(gltf_json(m, bin, mode), file);
  return file;
}

// An axis-aligned box [lo, hi], 12 triangles, outward winding.
inline TestMesh box_mesh(glm::vec3 lo, glm::vec3 hi) {
  TestMesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return m;
}

// An icosphere of radius r: subdivisions 0..6.
inline TestMesh sphere_mesh(float r, int subdivisions) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::uint32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                  4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                                  6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (auto& p : v) p = glm::normalize(p);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    std::vector<std::uint32_t> g;
    for (std::size_t i = 0; i < f.size(); i += 3) {
      std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2], ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(g);
  }
  TestMesh m;
  for (auto& p : v) m.positions.push_back(p * r);
  m.indices = f;
  return m;
}

}  // namespace sva::test
