#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <sva/io/binary_file.hpp>
#include "test_support.hpp"

using sva::io::BinaryReader;
using sva::io::BinaryWriter;

TEST_CASE("binary container round-trips and refuses damage") {
  auto dir = sva::test::temp_dir("binary");
  auto file = dir / "x.bin";
  BinaryWriter w;
  w.put<std::uint32_t>(42);
  w.put_string("hello");
  w.put_vector(std::vector<double>{1.5, -2.0});
  w.write_file(file, "SVATEST1", 3);
  {
    BinaryReader r(file, "SVATEST1", 3, "test");
    CHECK(r.get<std::uint32_t>() == 42);
    CHECK(r.get_string() == "hello");
    CHECK(r.get_vector<double>() == std::vector<double>{1.5, -2.0});
    r.expect_end();
  }
  CHECK_THROWS_WITH(BinaryReader(file, "SVATEST1", 4, "test"), Catch::Contains("version 3"));
  CHECK_THROWS_WITH(BinaryReader(file, "SVAOTHER", 3, "test"), Catch::Contains("bad magic"));
  CHECK_THROWS_WITH(BinaryReader(dir / "missing.bin", "SVATEST1", 3, "test"), Catch::Contains("no such file"));
  // Flip one payload byte: checksum.
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto corrupt = bytes;
  corrupt[40] ^= 0x5a;
  std::ofstream(dir / "c.bin", std::ios::binary) << corrupt;
  CHECK_THROWS_WITH(BinaryReader(dir / "c.bin", "SVATEST1", 3, "test"), Catch::Contains("checksum"));
  std::ofstream(dir / "t.bin", std::ios::binary) << bytes.substr(0, bytes.size() - 3);
  CHECK_THROWS_WITH(BinaryReader(dir / "t.bin", "SVATEST1", 3, "test"), Catch::Contains("truncated"));
  std::ofstream(dir / "e.bin", std::ios::binary) << "";
  CHECK_THROWS_WITH(BinaryReader(dir / "e.bin", "SVATEST1", 3, "test"), Catch::Contains("empty"));
  // A huge length prefix inside a valid container is refused, not allocated.
  BinaryReader r(std::vector<std::uint8_t>{0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x7f}, "mem");
  CHECK_THROWS_WITH(r.get_vector<double>(), Catch::Contains("exceeds"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("binary container: a checksum weighed beside the parse reads the same and still refuses damage") {
  using sva::io::Checksum;
  auto dir = sva::test::temp_dir("binary-alongside");
  const std::vector<double> values(20000, 0.25);  // enough bytes that the checksum may still run while they are read
  BinaryWriter w;
  w.put<std::uint32_t>(42);
  w.put_vector(values);
  w.write_file(dir / "x.bin", "SVATEST1", 3);
  {
    BinaryReader r(dir / "x.bin", "SVATEST1", 3, 3, "test", Checksum::alongside);
    CHECK(r.get<std::uint32_t>() == 42);
    CHECK(r.get_vector<double>() == values);
    r.expect_end();
    CHECK_NOTHROW(r.verify());
    CHECK_NOTHROW(r.verify());
  }
  std::string bytes;
  {
    std::ifstream in(dir / "x.bin", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  // A flipped byte anywhere in the payload: the constructor returns, the parse reads what is there, verify refuses it
  // (and again when asked again); weighed first, the constructor refuses it.
  for (const std::size_t at : {std::size_t{32}, std::size_t{40}, bytes.size() / 2, bytes.size() - 1}) {
    auto corrupt = bytes;
    corrupt[at] ^= 0x5a;
    std::ofstream(dir / "c.bin", std::ios::binary | std::ios::trunc) << corrupt;
    INFO("byte " << at << " of " << bytes.size());
    BinaryReader r(dir / "c.bin", "SVATEST1", 3, 3, "test", Checksum::alongside);
    CHECK_THROWS_WITH(r.verify(), Catch::Contains("c.bin") && Catch::Contains("checksum"));
    CHECK_THROWS_WITH(r.verify(), Catch::Contains("checksum"));
    CHECK_THROWS_WITH(BinaryReader(dir / "c.bin", "SVATEST1", 3, 3, "test", Checksum::first),
                      Catch::Contains("checksum"));
  }
  // Left unverified (a parse that threw past it): the checksum's thread is joined with the reader, nothing thrown.
  CHECK_NOTHROW(BinaryReader(dir / "c.bin", "SVATEST1", 3, 3, "test", Checksum::alongside));
  std::filesystem::remove_all(dir);
}

TEST_CASE("binary container: a file cut short says truncated with both sizes, even inside the header") {
  auto dir = sva::test::temp_dir("binary-cut");
  BinaryWriter w;
  w.put<std::uint64_t>(7);
  w.write_file(dir / "x.bin", "SVATEST1", 3);
  std::string bytes;
  {
    std::ifstream in(dir / "x.bin", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  REQUIRE(bytes.size() == 40);
  std::ofstream(dir / "head.bin", std::ios::binary) << bytes.substr(0, 20);  // the magic intact, the header cut
  CHECK_THROWS_WITH(
      BinaryReader(dir / "head.bin", "SVATEST1", 3, "test"),
      Catch::Contains("head.bin: truncated test file: 20 bytes, its header alone is 32") && !Catch::Contains("magic"));
  std::ofstream(dir / "body.bin", std::ios::binary) << bytes.substr(0, 36);
  CHECK_THROWS_WITH(
      BinaryReader(dir / "body.bin", "SVATEST1", 3, "test"),
      Catch::Contains("body.bin: truncated test file: expected 40 bytes") && Catch::Contains("the file has 36"));
  std::ofstream(dir / "pad.bin", std::ios::binary) << bytes + "xx";
  CHECK_THROWS_WITH(BinaryReader(dir / "pad.bin", "SVATEST1", 3, "test"), Catch::Contains("padded"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("atomic write: a refused rename reports its own error, not the clean-up's") {
  auto dir = sva::test::temp_dir("binary-rename");
  std::filesystem::create_directories(dir / "folder");
  BinaryWriter w;
  w.put<std::uint32_t>(1);
  CHECK_THROWS_WITH(w.write_file(dir / "folder", "SVATEST1", 3),
                    Catch::Contains("cannot rename the temporary file into place (Is a directory)"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("a binary file whose size the stream cannot tell (a pipe) is read and checked as a stream") {
  auto dir = sva::test::temp_dir("binary-pipe");
  BinaryWriter w;
  w.put<std::uint32_t>(7);
  w.put_vector(std::vector<float>(1000, 0.25f));
  w.write_file(dir / "x.bin", "SVATEST1", 3);
  std::string bytes;
  {
    std::ifstream in(dir / "x.bin", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto fifo = dir / "pipe";
  auto read_through_pipe = [&](const std::string& content) {
    std::filesystem::remove(fifo);
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    std::thread writer([&] { std::ofstream(fifo, std::ios::binary) << content; });
    try {
      BinaryReader r(fifo, "SVATEST1", 3, "test");
      writer.join();
      return r;
    } catch (...) {
      writer.join();
      throw;
    }
  };
  BinaryReader r = read_through_pipe(bytes);
  CHECK(r.get<std::uint32_t>() == 7);
  CHECK(r.get_vector<float>() == std::vector<float>(1000, 0.25f));
  r.expect_end();
  std::string corrupt = bytes;
  corrupt[100] ^= 0x5a;
  CHECK_THROWS_WITH(read_through_pipe(corrupt), Catch::Contains("checksum"));
  CHECK_THROWS_WITH(read_through_pipe(bytes.substr(0, 20)), Catch::Contains("truncated test file: 20 bytes"));
  CHECK_THROWS_WITH(read_through_pipe(""), Catch::Contains("empty file"));
}
