#include <catch2/catch.hpp>

#include <fstream>

#include "io/binary_file.hpp"
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
