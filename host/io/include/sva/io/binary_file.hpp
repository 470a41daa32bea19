#pragma once
// Versioned, checksummed binary container shared by datasets, maps and
// recordings. Layout (little-endian):
//   magic[8] | u32 version | u32 reserved | u64 payload_bytes | u64 fnv1a64(payload) | payload
// Files are written to a temporary name and renamed, so a crash or Ctrl-C never
// leaves a partial file that looks complete.
#include <sva/error.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace sva::io {

std::uint64_t fnv1a64(const std::uint8_t* data, std::size_t size);

class BinaryWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_array(const T* v, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(v);
    bytes_.insert(bytes_.end(), p, p + n * sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put<std::uint64_t>(v.size());
    put_array(v.data(), v.size());
  }
  void put_string(std::string_view s) {
    put<std::uint64_t>(s.size());
    put_array(s.data(), s.size());
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

  // Write header + payload atomically (temp file + rename).
  void write_file(const std::filesystem::path& file, std::string_view magic8, std::uint32_t version) const;

 private:
  std::vector<std::uint8_t> bytes_;
};

class BinaryReader {
 public:
  // Read and validate the whole file: magic, version, size and checksum.
  // `what` names the kind of file in messages ("dataset", "map").
  BinaryReader(const std::filesystem::path& file, std::string_view magic8, std::uint32_t version,
               std::string_view what);
  // The same, accepting versions oldest..version (a reader that converts older files).
  BinaryReader(const std::filesystem::path& file, std::string_view magic8, std::uint32_t oldest, std::uint32_t version,
               std::string_view what);
  std::uint32_t version() const { return version_; }
  // For in-memory payloads (tests).
  BinaryReader(std::vector<std::uint8_t> payload, std::string name);

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }
  template <class T>
  void get_array(T* out, std::size_t n) {
    if (n > remaining() / sizeof(T)) fail("truncated array of " + std::to_string(n) + " items");
    if (n) std::memcpy(out, take(n * sizeof(T)), n * sizeof(T));
  }
  template <class T>
  std::vector<T> get_vector(std::size_t max_items = SIZE_MAX) {
    auto n = get<std::uint64_t>();
    if (n > max_items || n > remaining() / sizeof(T)) fail("array length " + std::to_string(n) + " exceeds the file");
    std::vector<T> v(n);
    get_array(v.data(), n);
    return v;
  }
  std::string get_string(std::size_t max_len = 1 << 20);
  std::size_t remaining() const { return payload_.size() - pos_; }
  void expect_end();
  [[noreturn]] void fail(const std::string& what) const;
  const std::string& name() const { return name_; }

 private:
  void check_header(const std::vector<char>& head, std::size_t file_size, std::string_view magic8, std::uint32_t oldest,
                    std::uint32_t version, std::string_view what);
  const std::uint8_t* take(std::size_t n);
  std::vector<std::uint8_t> payload_;
  std::size_t pos_ = 0;
  std::string name_;
  std::uint32_t version_ = 0;
};

// The magic of a file, or "" if it cannot be read (used to dispatch `sva inspect`).
std::string peek_magic(const std::filesystem::path& file);

}  // namespace sva::io
