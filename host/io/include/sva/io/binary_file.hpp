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
#include <future>
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

// When a reader weighs its payload's checksum: before its constructor returns, or (a payload of 64 KiB or more) on a
// thread of its own while the caller parses (FNV-1a is serial, about 4 cycles a byte: 0.15 s of a 112 MB map's 0.42 s
// load). The caller then calls verify() before it trusts what it parsed, and also when its parse fails, so that a
// corrupt file is named corrupt rather than by what its damage broke (parse_verified does both). The parse must take
// any bytes: every reader's does, they are fuzzed.
enum class Checksum { first, alongside };

class BinaryReader {
 public:
  // Read and validate the whole file: magic, version, size and checksum.
  // `what` names the kind of file in messages ("dataset", "map").
  BinaryReader(const std::filesystem::path& file, std::string_view magic8, std::uint32_t version,
               std::string_view what);
  // The same, accepting versions oldest..version (a reader that converts older files), the checksum weighed `when`.
  BinaryReader(const std::filesystem::path& file, std::string_view magic8, std::uint32_t oldest, std::uint32_t version,
               std::string_view what, Checksum when = Checksum::first);
  // Waits for a checksum still running alongside, and throws sva::Error naming the file if it does not match (again
  // on every later call). Does nothing when it was weighed first, or matched.
  void verify();
  // Runs parse() and then verify(); when parse() throws, verify() first, so that a corrupt file is named corrupt.
  template <class Parse>
  void parse_verified(Parse&& parse) {
    try {
      parse();
    } catch (...) {
      verify();
      throw;
    }
    verify();
  }
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
  std::uint64_t expected_sum_ = 0;
  bool corrupt_ = false;            // the checksum alongside did not match
  std::future<std::uint64_t> sum_;  // the checksum alongside: after payload_, so that it is joined before that goes
};

// The magic of a file, or "" if it cannot be read (used to dispatch `sva inspect`).
std::string peek_magic(const std::filesystem::path& file);

}  // namespace sva::io
