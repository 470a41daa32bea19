#pragma once
// Shared by the libFuzzer harnesses (tests/fuzz/fuzz_*.cpp). A harness feeds its input to one parser; sva::Error is
// the expected outcome for bad input, anything else (another exception, a crash, a sanitizer report, a timeout, an
// allocation past -rss_limit_mb) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include <sva/io/binary_file.hpp>

namespace sva::fuzz {

// The loaders that only take a path read the input from this file: one per process (parallel jobs do not
// collide), in /dev/shm when there is one so that it costs no disk write.
inline std::filesystem::path write_input(std::span<const std::uint8_t> bytes, const char* name) {
  static const std::filesystem::path dir = [] {
    std::filesystem::path base =
        std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    auto d = base / ("sva-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  auto file = dir / name;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) std::abort();
  return file;
}

// The binary container (host/io/include/sva/io/binary_file.hpp) is checksummed, so almost every mutation would stop at
// the checksum. Unless bit 0 of the reserved header field is set (the fuzzer then exercises the raw header checks), the
// magic, payload size and checksum are rewritten to match the payload, which sends the mutation on to the payload
// parser.
inline std::vector<std::uint8_t> repair_container(std::span<const std::uint8_t> in, const char* magic8) {
  constexpr std::size_t kHeader = 32;
  std::vector<std::uint8_t> bytes(in.begin(), in.end());
  if (bytes.size() < kHeader || (bytes[12] & 1)) return bytes;
  std::memcpy(bytes.data(), magic8, 8);
  const std::uint64_t size = bytes.size() - kHeader;
  const std::uint64_t sum = io::fnv1a64(bytes.data() + kHeader, size);
  std::memcpy(bytes.data() + 16, &size, 8);
  std::memcpy(bytes.data() + 24, &sum, 8);
  return bytes;
}

}  // namespace sva::fuzz
