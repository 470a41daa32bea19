// The confusion matrix of a run and its tables (confusion.hpp).
#include <sva/error.hpp>
#include <sva/eval/confusion.hpp>

#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>

namespace sva::eval {

namespace {

// Indices of `names` in family order: the family-less objects first (scene order), then every family's members
// together, families in the order they first appear. Stable within a group.
std::vector<std::size_t> family_order(const std::vector<std::string>& families) {
  std::vector<std::string> groups{""};
  for (const std::string& f : families)
    if (std::find(groups.begin(), groups.end(), f) == groups.end()) groups.push_back(f);
  std::vector<std::size_t> order;
  for (const std::string& g : groups)
    for (std::size_t i = 0; i < families.size(); ++i)
      if (families[i] == g) order.push_back(i);
  return order;
}

std::string family_of(const EvalResult& r, const std::string& object) {
  for (std::size_t i = 0; i < r.objects.size(); ++i)
    if (r.objects[i] == object) return i < r.families.size() ? r.families[i] : "";
  return "";
}

std::vector<std::size_t> objects_with_trials(const EvalResult& r) {
  std::vector<bool> has(r.objects.size(), false);
  for (const TrialResult& t : r.trials)
    if (t.object < has.size()) has[t.object] = true;
  std::vector<std::string> families(r.objects.size());
  for (std::size_t i = 0; i < families.size(); ++i) families[i] = i < r.families.size() ? r.families[i] : "";
  std::vector<std::size_t> rows;
  for (std::size_t i : family_order(families))
    if (has[i]) rows.push_back(i);
  return rows;
}

}  // namespace

std::size_t Confusion::trials(std::size_t row) const {
  std::size_t n = 0;
  for (std::size_t c : counts.at(row)) n += c;
  return n;
}

std::size_t Confusion::right(std::size_t row) const {
  return truth_column.at(row) < 0 ? 0 : counts.at(row)[static_cast<std::size_t>(truth_column[row])];
}

Confusion confusion_at(const EvalResult& result, std::size_t readings) {
  if (readings == 0 || readings > result.max_readings)
    throw Error("confusion matrix at " + std::to_string(readings) + " readings: the run has 1 to " +
                std::to_string(result.max_readings) + " readings per trial");
  const std::vector<std::string>& map_names = result.map_objects.empty() ? result.objects : result.map_objects;
  Confusion c;
  c.readings = readings;
  std::vector<std::string> map_families;
  for (const std::string& m : map_names) map_families.push_back(family_of(result, m));
  const std::vector<std::size_t> columns = family_order(map_families);
  std::vector<std::size_t> column_of(map_names.size());
  for (std::size_t k = 0; k < columns.size(); ++k) {
    column_of[columns[k]] = k;
    c.estimates.push_back(map_names[columns[k]]);
    c.estimate_families.push_back(map_families[columns[k]]);
  }
  const std::vector<std::size_t> rows = objects_with_trials(result);
  std::vector<std::size_t> row_of(result.objects.size(), 0);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    row_of[rows[k]] = k;
    c.truths.push_back(result.objects[rows[k]]);
    c.truth_families.push_back(rows[k] < result.families.size() ? result.families[rows[k]] : "");
    const auto at = std::find(c.estimates.begin(), c.estimates.end(), c.truths.back());
    c.truth_column.push_back(at == c.estimates.end() ? -1 : at - c.estimates.begin());
  }
  c.counts.assign(rows.size(), std::vector<std::size_t>(columns.size(), 0));
  for (const TrialResult& t : result.trials) {
    if (t.steps.size() < readings) continue;  // a trial cut short (a test set with fewer readings)
    const std::uint32_t est = t.steps[readings - 1].estimated_object;
    if (est >= column_of.size())
      throw Error("confusion matrix: estimated object " + std::to_string(est) + " is not one of the map's " +
                  std::to_string(map_names.size()));
    ++c.counts[row_of[t.object]][column_of[est]];
  }
  return c;
}

std::vector<FamilyScore> family_scores(const Confusion& c) {
  std::vector<FamilyScore> out;
  for (std::size_t r = 0; r < c.truths.size(); ++r) {
    const std::string& f = c.truth_families[r];
    if (f.empty()) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const FamilyScore& s) { return s.family == f; });
    if (it == out.end()) it = out.insert(out.end(), FamilyScore{f});
    ++it->members;
    it->trials += c.trials(r);
    it->right += c.right(r);
    for (std::size_t k = 0; k < c.estimates.size(); ++k)
      if (c.estimate_families[k] == f && static_cast<std::ptrdiff_t>(k) != c.truth_column[r])
        it->within_family += c.counts[r][k];
  }
  return out;
}

namespace {

// What a row's object is most often wrongly taken for, with that count; "" when never wrong.
std::pair<std::string, std::size_t> most_confused(const Confusion& c, std::size_t row) {
  std::pair<std::string, std::size_t> best{"", 0};
  for (std::size_t k = 0; k < c.estimates.size(); ++k)
    if (static_cast<std::ptrdiff_t>(k) != c.truth_column[row] && c.counts[row][k] > best.second)
      best = {c.estimates[k], c.counts[row][k]};
  return best;
}

std::string percent(std::size_t part, std::size_t whole) {
  char b[16];
  std::snprintf(b, sizeof b, "%5.1f%%", whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0);
  return b;
}

void check_one_run(const std::vector<Confusion>& cs) {
  if (cs.empty()) throw Error("confusion tables: no reading counts");
  for (const Confusion& c : cs)
    if (c.truths != cs.front().truths || c.estimates != cs.front().estimates)
      throw Error("confusion tables: the confusions are of different runs");
}

std::string object_table(const std::vector<Confusion>& cs) {
  std::string out = "per object (share right at each reading count; what it is most often taken for at " +
                    std::to_string(cs.back().readings) + "):\n";
  char line[512];
  std::snprintf(line, sizeof line, "  %-24s %-16s %6s", "object", "family", "trials");
  out += line;
  for (const Confusion& c : cs) out += "   acc@" + std::to_string(c.readings);
  out += "   taken for\n";
  for (std::size_t r = 0; r < cs.front().truths.size(); ++r) {
    std::snprintf(line, sizeof line, "  %-24s %-16s %6zu", cs.front().truths[r].c_str(),
                  cs.front().truth_families[r].empty() ? "-" : cs.front().truth_families[r].c_str(),
                  cs.front().trials(r));
    out += line;
    for (const Confusion& c : cs) out += "  " + percent(c.right(r), c.trials(r));
    const auto [name, n] = most_confused(cs.back(), r);
    out += name.empty() ? "   -\n" : "   " + name + " (" + std::to_string(n) + ")\n";
  }
  return out;
}

std::string family_table(const std::vector<Confusion>& cs) {
  std::vector<std::vector<FamilyScore>> scores;
  for (const Confusion& c : cs) scores.push_back(family_scores(c));
  if (scores.front().empty()) return "";
  std::string out = "per family (share of its members' trials right; wrong ones taken for another member):\n";
  char line[256];
  std::snprintf(line, sizeof line, "  %-16s %7s %6s", "family", "members", "trials");
  out += line;
  for (const Confusion& c : cs) out += "   acc@" + std::to_string(c.readings) + "  in-family";
  out += "\n";
  for (std::size_t f = 0; f < scores.front().size(); ++f) {
    const FamilyScore& s0 = scores.front()[f];
    std::snprintf(line, sizeof line, "  %-16s %7zu %6zu", s0.family.c_str(), s0.members, s0.trials);
    out += line;
    for (const auto& s : scores) {
      const FamilyScore& x = s[f];
      out += "  " + percent(x.right, x.trials) + "  " + percent(x.within_family, x.trials - x.right) + "   ";
    }
    out += "\n";
  }
  return out;
}

}  // namespace

std::string format_confusion_tables(const std::vector<Confusion>& confusions) {
  check_one_run(confusions);
  return object_table(confusions) + family_table(confusions);
}

std::string confusion_json(const std::vector<Confusion>& confusions) {
  using nlohmann::json;
  check_one_run(confusions);
  json j, matrices = json::array(), objects = json::array(), families = json::array();
  for (const Confusion& c : confusions)
    matrices.push_back({{"readings", c.readings},
                        {"truths", c.truths},
                        {"truth_families", c.truth_families},
                        {"estimates", c.estimates},
                        {"estimate_families", c.estimate_families},
                        {"counts", c.counts}});
  const Confusion& first = confusions.front();
  for (std::size_t r = 0; r < first.truths.size(); ++r) {
    json acc = json::object();
    for (const Confusion& c : confusions)
      acc[std::to_string(c.readings)] = c.trials(r) ? static_cast<double>(c.right(r)) / c.trials(r) : 0.0;
    objects.push_back({{"object", first.truths[r]},
                       {"family", first.truth_families[r]},
                       {"trials", first.trials(r)},
                       {"in_map", first.truth_column[r] >= 0},
                       {"accuracy", acc}});
  }
  std::vector<std::vector<FamilyScore>> scores;
  for (const Confusion& c : confusions) scores.push_back(family_scores(c));
  for (std::size_t f = 0; f < scores.front().size(); ++f) {
    json acc = json::object(), within = json::object();
    for (std::size_t k = 0; k < confusions.size(); ++k) {
      const FamilyScore& s = scores[k][f];
      acc[std::to_string(confusions[k].readings)] = s.accuracy();
      within[std::to_string(confusions[k].readings)] = s.within_family;
    }
    families.push_back({{"family", scores.front()[f].family},
                        {"members", scores.front()[f].members},
                        {"trials", scores.front()[f].trials},
                        {"accuracy", acc},
                        {"wrong_within_family", within}});
  }
  j["confusion"] = std::move(matrices);
  j["objects"] = std::move(objects);
  j["families"] = std::move(families);
  return io::dump_json(j, 1) + "\n";
}

}  // namespace sva::eval
