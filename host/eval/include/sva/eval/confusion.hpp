#pragma once
// Which objects are taken for which (`sva eval --confusion`): the confusion matrix of a run at chosen reading
// counts, ordered by look-alike family (SceneObject::family), the accuracy per object and per family, and the
// matrix drawn as a PNG. docs/evaluation.md, "Look-alikes".
//
//   std::vector<eval::Confusion> c = {eval::confusion_at(result, 15), eval::confusion_at(result, 30)};
//   std::fputs(eval::format_confusion_tables(c).c_str(), stdout);
//   io::write_text_file("conf.json", eval::confusion_json(c));
//   eval::write_confusion_figure(c.back(), "conf.png");
#include <sva/eval/results.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace sva::eval {

// The estimates of every trial after `readings` readings. Rows are the test set's objects that have trials,
// columns the map's objects, both in family order: the objects without a family first in the scene's order,
// then each family's members together, families in the order they first appear.
struct Confusion {
  std::size_t readings = 0;
  std::vector<std::string> truths, truth_families;        // rows
  std::vector<std::string> estimates, estimate_families;  // columns
  std::vector<std::vector<std::size_t>> counts;           // [row][column]: trials of the row's object named the column
  std::vector<std::ptrdiff_t> truth_column;               // the row's object's column, -1 when the map lacks it

  std::size_t trials(std::size_t row) const;
  std::size_t right(std::size_t row) const;  // the diagonal (0 for an object the map lacks)
};

// Throws sva::Error when `readings` is 0 or beyond the run's max_readings.
Confusion confusion_at(const EvalResult& result, std::size_t readings);

// How well a family's members are told apart at one reading count: its members' trials, those right, and of
// the wrong ones those taken for another member of the same family.
struct FamilyScore {
  std::string family;
  std::size_t members = 0, trials = 0, right = 0, within_family = 0;
  double accuracy() const { return trials ? static_cast<double>(right) / static_cast<double>(trials) : 0.0; }
};
std::vector<FamilyScore> family_scores(const Confusion& confusion);

// The per-object accuracy table (one column per confusion's reading count, and what the object is most often
// taken for at the last), then the per-family table when the scene has families. Confusions of one run.
std::string format_confusion_tables(const std::vector<Confusion>& confusions);
// {"confusion": [{"readings", "truths", "truth_families", "estimates", "estimate_families", "counts"}...],
//  "objects": [{"object", "family", "trials", "accuracy": {"15": a, ...}}], "families": [...]}
std::string confusion_json(const std::vector<Confusion>& confusions);
// The matrix, each row as the share of its trials, families boxed; PNG, written atomically.
void write_confusion_figure(const Confusion& confusion, const std::string& scene, const std::filesystem::path& file);

}  // namespace sva::eval
