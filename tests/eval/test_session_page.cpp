// The data of an sva view page (docs/view.md, "Names are text"): names from files embed as JSON that no name can end
// or keep open, and decode to the names as written. The browser's side is tests/view/browser_test.py.
#include <catch2/catch.hpp>

#include <sva/eval/session_view.hpp>
#include <sva/io/text_file.hpp>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

TEST_CASE("view page: hostile names stay inside the data's script and decode exactly") {
  const auto dir = sva::test::temp_dir("session-page");
  // A stand-in three.js: the page's data is the subject here, not the libraries.
  std::filesystem::create_directories(dir / "three/examples/js/controls");
  std::ofstream(dir / "three/three.min.js") << "var THREE = {};\n";
  std::ofstream(dir / "three/examples/js/controls/OrbitControls.js") << "THREE.OrbitControls = function () {};\n";
  ::setenv("SVA_THREE_JS", (dir / "three").c_str(), 1);

  const std::vector<std::string> names = {"</script><script>alert(1)</script>",
                                          "<!--<script>",
                                          "a & b > c",
                                          "\"quoted\" 'single'",
                                          "\xe2\x80\xae"
                                          "gnp.exe",
                                          "bell\x07"};
  nlohmann::json data = {{"title", "</SCRIPT >"}, {"objects", names}};
  sva::view::write_session_page(dir / "page.html", data);
  const std::string page = sva::io::read_text_file(dir / "page.html", "page");

  const std::string open = "<script id=\"sva-data\" type=\"application/json\">\n";
  const auto start = page.find(open);
  REQUIRE(start != std::string::npos);
  const auto end = page.find("\n</script>", start);
  REQUIRE(end != std::string::npos);
  const std::string text = page.substr(start + open.size(), end - start - open.size());
  // Nothing in the data that HTML's script parsing reads: the element ends at its own end tag.
  CHECK(text.find('<') == std::string::npos);
  CHECK(text.find('>') == std::string::npos);
  CHECK(text.find('&') == std::string::npos);
  CHECK(nlohmann::json::parse(text) == data);

  // A name that is not UTF-8 (a map file's bytes): the page is still written, the byte shown as U+FFFD.
  data["objects"][0] = "bad \xff byte";
  sva::view::write_session_page(dir / "bad.html", data);
  CHECK(sva::io::read_text_file(dir / "bad.html", "page").find("bad \xef\xbf\xbd byte") != std::string::npos);
}
