#include <sva/io/binary_file.hpp>

#include <sva/io/text_file.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

namespace sva::io {

namespace {
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;
// Below this a payload's checksum (about 85 us at 4 cycles a byte) is weighed first: a thread costs a fair part of it.
constexpr std::size_t kAlongsideBytes = 64 << 10;
}  // namespace

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
                           std::uint32_t version, std::string_view what, Checksum when)
    : name_(file.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) fail("no such file");
  if (std::filesystem::is_directory(file, ec)) fail("is a directory, expected a " + std::string(what) + " file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail("cannot open for reading");
  in.seekg(0, std::ios::end);
  // The payload is read straight into its buffer: a 100 MB map went through a byte iterator and a second copy, two
  // thirds of its load time (2026-11-29). A file whose size the stream cannot tell (a pipe) is read as a stream.
  const std::streamoff end = in.tellg();
  std::vector<char> head;  // the header, or the whole file when its size is not known
  if (end >= 0) {
    in.seekg(0);
    head.resize(std::min(static_cast<std::size_t>(end), kHeaderBytes));
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    if (!in) fail("cannot read");
  } else {
    in.clear();  // the failed seek
    head.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::size_t file_size = end >= 0 ? static_cast<std::size_t>(end) : head.size();
  check_header(head, file_size, magic8, oldest, version, what);
  std::uint64_t sum;
  std::memcpy(&sum, head.data() + 24, 8);
  if (end >= 0) {
    payload_.resize(file_size - kHeaderBytes);
    in.read(reinterpret_cast<char*>(payload_.data()), static_cast<std::streamsize>(payload_.size()));
    if (static_cast<std::size_t>(in.gcount()) != payload_.size())  // it shrank while read
      fail("truncated " + std::string(what) + " file: it ended after " +
           std::to_string(kHeaderBytes + static_cast<std::size_t>(in.gcount())) + " of " + std::to_string(file_size) +
           " bytes while it was read");
  } else {
    payload_.assign(head.begin() + kHeaderBytes, head.end());
  }
  expected_sum_ = sum;
  if (when == Checksum::alongside && payload_.size() >= kAlongsideBytes) {
    try {
      sum_ = std::async(std::launch::async, [p = payload_.data(), n = payload_.size()] { return fnv1a64(p, n); });
      return;
    } catch (const std::system_error&) {  // no thread to be had: weighed here, as first
    }
  }
  if (fnv1a64(payload_.data(), payload_.size()) != sum) fail("checksum mismatch: the file is corrupt");
}

void BinaryReader::verify() {
  if (sum_.valid()) corrupt_ = sum_.get() != expected_sum_;
  if (corrupt_) fail("checksum mismatch: the file is corrupt");
}

// The header's checks, on its bytes (`head`, at least its first kHeaderBytes when the file has them) and the file's
// size: the magic, the version this build reads, and a size that matches the payload's.
void BinaryReader::check_header(const std::vector<char>& head, std::size_t file_size, std::string_view magic8,
                                std::uint32_t oldest, std::uint32_t version, std::string_view what) {
  if (file_size == 0) fail("empty file, expected a " + std::string(what) + " file");
  if (head.size() < 8 || std::memcmp(head.data(), magic8.data(), 8) != 0)
    fail("not an sva " + std::string(what) + " file (bad magic)");
  if (file_size < kHeaderBytes)  // the magic is right: the file was cut short, e.g. by a full disk
    fail("truncated " + std::string(what) + " file: " + std::to_string(file_size) + " bytes, its header alone is " +
         std::to_string(kHeaderBytes));
  std::uint32_t file_version;
  std::uint64_t size;
  std::memcpy(&file_version, head.data() + 8, 4);
  std::memcpy(&size, head.data() + 16, 8);
  if (file_version < oldest || file_version > version)
    fail(std::string(what) + " format version " + std::to_string(file_version) + ", this build reads version " +
         (oldest == version ? std::to_string(version) : std::to_string(oldest) + " to " + std::to_string(version)));
  version_ = file_version;
  if (size != file_size - kHeaderBytes)
    fail(std::string(size > file_size - kHeaderBytes ? "truncated " : "padded ") + std::string(what) +
         " file: expected " + std::to_string(kHeaderBytes + size) + " bytes (a " + std::to_string(kHeaderBytes) +
         "-byte header and " + std::to_string(size) + " payload bytes), the file has " + std::to_string(file_size));
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
