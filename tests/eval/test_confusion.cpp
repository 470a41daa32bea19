// The confusion matrix, its family order and its tables (host/eval/src/eval/confusion.cpp) on results made by hand.
#include <catch2/catch.hpp>

#include <sva/error.hpp>
#include <sva/eval/confusion.hpp>

#include <array>
#include <filesystem>

#include <nlohmann/json.hpp>

using namespace sva::eval;
using Catch::Contains;

namespace {

// Objects: a plain one, then two families interleaved in the scene's order, so that the family order shows.
EvalResult result_by_hand() {
  EvalResult r;
  r.scene = "hand";
  r.max_readings = 2;
  r.objects = {"cup_s", "box", "clamp_s", "cup_l", "clamp_l"};
  r.families = {"cups", "", "clamps", "cups", "clamps"};
  r.map_objects = r.objects;
  // (object, estimate at 1, estimate at 2)
  const std::vector<std::array<std::uint32_t, 3>> trials = {{0, 3, 0}, {0, 3, 3}, {3, 3, 3}, {2, 4, 2},
                                                            {2, 2, 2}, {4, 1, 4}, {1, 1, 1}};
  for (const auto& [object, first, second] : trials) {
    TrialResult t;
    t.object = object;
    for (std::uint32_t est : {first, second}) {
      StepResult s;
      s.estimated_object = est;
      s.correct = est == object;
      t.steps.push_back(s);
    }
    r.trials.push_back(t);
  }
  return r;
}

}  // namespace

TEST_CASE("confusion: rows and columns in family order, counts per trial, the diagonal right") {
  const EvalResult r = result_by_hand();
  const Confusion c = confusion_at(r, 2);
  CHECK(c.truths == std::vector<std::string>{"box", "cup_s", "cup_l", "clamp_s", "clamp_l"});
  CHECK(c.truth_families == std::vector<std::string>{"", "cups", "cups", "clamps", "clamps"});
  CHECK(c.estimates == c.truths);
  CHECK(c.truth_column == std::vector<std::ptrdiff_t>{0, 1, 2, 3, 4});
  CHECK(c.counts[1] == std::vector<std::size_t>{0, 1, 1, 0, 0});  // cup_s: once right, once the large cup
  CHECK(c.trials(1) == 2);
  CHECK(c.right(1) == 1);
  CHECK(c.right(3) == 2);
  const Confusion first = confusion_at(r, 1);
  CHECK(first.right(1) == 0);
  CHECK(first.counts[4] == std::vector<std::size_t>{1, 0, 0, 0, 0});  // clamp_l taken for the box

  const std::vector<FamilyScore> f = family_scores(first);
  REQUIRE(f.size() == 2);
  CHECK(f[0].family == "cups");
  CHECK(f[0].members == 2);
  CHECK(f[0].trials == 3);
  CHECK(f[0].right == 1);
  CHECK(f[0].within_family == 2);  // both wrong cups named the other cup
  CHECK(f[1].family == "clamps");
  CHECK(f[1].right == 1);
  CHECK(f[1].within_family == 1);  // clamp_s as clamp_l; clamp_l as the box is outside the family

  CHECK_THROWS_WITH(confusion_at(r, 0), Contains("1 to 2"));
  CHECK_THROWS_WITH(confusion_at(r, 3), Contains("1 to 2"));
}

TEST_CASE("confusion: objects the map lacks are rows without a right column, objects without trials no rows") {
  EvalResult r = result_by_hand();
  r.map_objects = {"cup_s", "box", "cup_l", "clamp_l"};  // clamp_s held out; map ids follow this list
  const std::uint32_t to_map[] = {0, 1, 3, 2, 3};        // clamp_s's estimates become the large clamp
  for (TrialResult& t : r.trials)
    for (StepResult& s : t.steps) s.estimated_object = to_map[s.estimated_object];
  r.trials.erase(r.trials.begin() + 6);  // the box has no trials now
  const Confusion c = confusion_at(r, 2);
  CHECK(c.truths == std::vector<std::string>{"cup_s", "cup_l", "clamp_s", "clamp_l"});
  CHECK(c.estimates == std::vector<std::string>{"box", "cup_s", "cup_l", "clamp_l"});
  CHECK(c.truth_column[2] == -1);
  CHECK(c.right(2) == 0);
  CHECK(c.trials(2) == 2);
}

TEST_CASE("confusion: the tables, the JSON and the figure") {
  const EvalResult r = result_by_hand();
  const std::vector<Confusion> cs = {confusion_at(r, 1), confusion_at(r, 2)};
  const std::string tables = format_confusion_tables(cs);
  CHECK_THAT(tables, Contains("acc@1") && Contains("acc@2") && Contains("per family") && Contains("clamps"));
  CHECK_THAT(tables, Contains("cup_l (1)"));  // cup_s is taken for the large cup once at 2 readings
  const auto j = nlohmann::json::parse(confusion_json(cs));
  CHECK(j["confusion"].size() == 2);
  CHECK(j["confusion"][1]["counts"][1][2] == 1);
  CHECK(j["objects"][1]["object"] == "cup_s");
  CHECK(j["objects"][1]["accuracy"]["2"].get<double>() == Approx(0.5));
  CHECK(j["families"][1]["accuracy"]["2"].get<double>() == Approx(1.0));

  const auto png = std::filesystem::temp_directory_path() / "sva_test_confusion.png";
  write_confusion_figure(cs.back(), r.scene, png);
  CHECK(std::filesystem::file_size(png) > 100);
  std::filesystem::remove(png);
  CHECK_THROWS_WITH(write_confusion_figure(Confusion{}, "x", png), Contains("no trials"));
  CHECK_THROWS_WITH(format_confusion_tables({}), Contains("no reading counts"));
}
