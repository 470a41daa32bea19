#include <sva/io/binary_file.hpp>

#include <sva/io/text_file.hpp>

#include <fstream>

namespace sva::io {

namespace {
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;
}

std::uint64_t fnv1a64(const std::uint8_t* data, std::size_t size) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= data[i];
    h *= 1099511628211ull;
  }
  return h;
}

void BinaryWriter::write_file(const std::filesystem::path& file, std::string_view magic8, std::uint32_t version) const {
  if (magic8.size() != 8) throw std::logic_error("magic must be 8 bytes");
  write_file_atomically(file, [&](std::ostream& out) {
    const std::uint32_t reserved = 0;
    const std::uint64_t size = bytes_.size();
    const std::uint64_t sum = fnv1a64(bytes_.data(), bytes_.size());
    out.write(magic8.data(), 8);
    out.write(reinterpret_cast<const char*>(&version), 4);
    out.write(reinterpret_cast<const char*>(&reserved), 4);
    out.write(reinterpret_cast<const char*>(&size), 8);
    out.write(reinterpret_cast<const char*>(&sum), 8);
    out.write(reinterpret_cast<const char*>(bytes_.data()), static_cast<std::streamsize>(bytes_.size()));
  });
}

BinaryReader::BinaryReader(const std::filesystem::path& file, std::string_view magic8, std::uint32_t version,
                           std::string_view what)
    : BinaryReader(file, magic8, version, version, what) {}

BinaryReader::BinaryReader(const std::filesystem::path& file, std::string_view magic8, std::uint32_t oldest,
                           std::uint32_t version, std::string_view what)
    : name_(file.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) fail("no such file");
  if (std::filesystem::is_directory(file, ec)) fail("is a directory, expected a " + std::string(what) + " file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail("cannot open for reading");
  std::vector<char> all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (all.empty()) fail("empty file, expected a " + std::string(what) + " file");
  if (all.size() < 8 || std::memcmp(all.data(), magic8.data(), 8) != 0)
    fail("not an sva " + std::string(what) + " file (bad magic)");
  if (all.size() < kHeaderBytes)  // the magic is right: the file was cut short, e.g. by a full disk
    fail("truncated " + std::string(what) + " file: " + std::to_string(all.size()) + " bytes, its header alone is " +
         std::to_string(kHeaderBytes));
  std::uint32_t file_version;
  std::uint64_t size, sum;
  std::memcpy(&file_version, all.data() + 8, 4);
  std::memcpy(&size, all.data() + 16, 8);
  std::memcpy(&sum, all.data() + 24, 8);
  if (file_version < oldest || file_version > version)
    fail(std::string(what) + " format version " + std::to_string(file_version) + ", this build reads version " +
         (oldest == version ? std::to_string(version) : std::to_string(oldest) + " to " + std::to_string(version)));
  version_ = file_version;
  if (size != all.size() - kHeaderBytes)
    fail(std::string(size > all.size() - kHeaderBytes ? "truncated " : "padded ") + std::string(what) +
         " file: expected " + std::to_string(kHeaderBytes + size) + " bytes (a " + std::to_string(kHeaderBytes) +
         "-byte header and " + std::to_string(size) + " payload bytes), the file has " + std::to_string(all.size()));
  payload_.assign(all.begin() + kHeaderBytes, all.end());
  if (fnv1a64(payload_.data(), payload_.size()) != sum) fail("checksum mismatch: the file is corrupt");
}

BinaryReader::BinaryReader(std::vector<std::uint8_t> payload, std::string name)
    : payload_(std::move(payload)), name_(std::move(name)) {}

const std::uint8_t* BinaryReader::take(std::size_t n) {
  if (n > remaining()) fail("truncated payload");
  const auto* p = payload_.data() + pos_;
  pos_ += n;
  return p;
}

std::string BinaryReader::get_string(std::size_t max_len) {
  auto n = get<std::uint64_t>();
  if (n > max_len || n > remaining()) fail("string length " + std::to_string(n) + " is invalid");
  std::string s(reinterpret_cast<const char*>(take(n)), n);
  return s;
}

void BinaryReader::expect_end() {
  if (remaining() != 0) fail(std::to_string(remaining()) + " unexpected trailing bytes");
}

void BinaryReader::fail(const std::string& what) const { throw Error(name_ + ": " + what); }

std::string peek_magic(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char m[8];
  if (!in.read(m, 8)) return {};
  return std::string(m, 8);
}

}  // namespace sva::io
