// sva eval --html: a page per trial (session_view.cpp) and an index of them, the worst first.
#include <sva/base/progress.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/figure.hpp>
#include <sva/eval/session_view.hpp>
#include <sva/eval/trials.hpp>
#include <sva/io/text_file.hpp>

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace sva::view {

namespace {

// Text from files (scene and object names) as HTML text or a quoted attribute's value: shown, never parsed as markup.
std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else if (c == '\'')
      out += "&#39;";
    else
      out += c;
  }
  return out;
}

std::string page_name(std::size_t t) { return "trial-" + std::to_string(t) + ".html"; }

// The trials, worst first: wrong at the last reading, then the truth's lowest probability, then the largest
// translation error (ties in trial order).
std::vector<std::size_t> worst_first(const eval::EvalResult& r) {
  std::vector<std::size_t> order(r.trials.size());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
  const auto key = [&](std::size_t t) {
    const eval::StepResult& s = r.trials[t].steps.back();
    return std::make_tuple(s.correct ? 1 : 0, s.true_object_probability,
                           -(s.has_pose_error() ? s.translation_error_mm : 0.0));
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  return order;
}

std::string row(const eval::EvalResult& r, std::size_t t) {
  const eval::TrialResult& trial = r.trials[t];
  const eval::StepResult& s = trial.steps.back();
  char error[64] = "-";
  if (s.has_pose_error())
    std::snprintf(error, sizeof error, "%.2f mm, %.2f&deg;", s.translation_error_mm,
                  s.angular_error_rad * 57.29577951308232);
  char p[32];
  std::snprintf(p, sizeof p, "%.3f", s.true_object_probability);
  const std::string estimate = s.estimated_object < r.map_objects.size() ? r.map_objects[s.estimated_object] : "-";
  return "<tr><td><a href=\"" + page_name(t) + "\">trial " + std::to_string(t) + "</a></td><td>" +
         escape(r.objects[trial.object]) + "</td><td>" + escape(estimate) + "</td><td>" +
         (s.correct ? "right" : "<b>wrong</b>") + "</td><td>" + p + "</td><td>" + error + "</td></tr>\n";
}

std::string index_page(const eval::EvalResult& r, const std::vector<std::size_t>& order, std::size_t worst) {
  std::ostringstream html;
  const std::string head =
      "<tr><th>trial</th><th>object</th><th>estimate</th><th></th><th>p(truth)</th>"
      "<th>error</th></tr>\n";
  html << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << escape(r.scene)
       << ": sva eval</title><style>body{font:13px/1.4 \"DejaVu Sans\",sans-serif;margin:16px}"
          "table{border-collapse:collapse}td,th{padding:2px 10px;border-bottom:1px solid #ddd;text-align:left}"
          "img{max-width:100%}</style></head><body>\n<h1>"
       << escape(r.scene) << ": " << r.trials.size() << " trials of " << r.max_readings << " readings (seed " << r.seed
       << ", " << escape(r.method) << ", " << escape(r.backend) << ")</h1>\n"
       << "<img src=\"accuracy.png\" alt=\"accuracy and errors against the readings\">\n"
       << "<h2>The worst trials (at " << r.max_readings << " readings)</h2>\n<table>\n"
       << head;
  for (std::size_t k = 0; k < std::min(worst, order.size()); ++k) html << row(r, order[k]);
  html << "</table>\n<h2>Every trial</h2>\n<table>\n" << head;
  for (std::size_t t = 0; t < r.trials.size(); ++t) html << row(r, t);
  html << "</table>\n</body></html>\n";
  return html.str();
}

}  // namespace

TrialView trial_view(const Map& map, const Dataset& test, const eval::TrialGenerator& generator, std::size_t t,
                     std::uint64_t seed, const std::string& data_name) {
  eval::Trial trial = generator.make(t);
  TrialView v;
  v.readings = std::move(trial.readings);
  const std::int32_t object = eval::map_objects_of(map, test)[trial.object];
  if (object >= 0) v.truth = SessionTruth{static_cast<std::uint32_t>(object), trial.pose};
  v.title = test.scene.name + " trial " + std::to_string(t) + ": " + test.scene.objects[trial.object].name;
  v.source = data_name + ", trial " + std::to_string(t) + " (seed " + std::to_string(seed) + ")";
  return v;
}

std::size_t write_trial_pages(const std::filesystem::path& dir, const Map& map, const Dataset& test,
                              const eval::EvalOptions& options, const eval::EvalResult& result,
                              const eval::Curve& curve) {
  if (options.policy != eval::Policy::random)
    throw Error(
        "sva eval --html: pages are made for the random policy's trials (their readings are made again "
        "from the seed)");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(dir.string() + ": cannot create the folder: " + ec.message());
  eval::write_figure({curve}, dir / "accuracy.png");
  const eval::TrialGenerator generator(test, map.pose_space(), options.seed, options.max_readings, options.data_name);
  util::Progress progress("eval pages", result.trials.size());
  for (std::size_t t = 0; t < result.trials.size(); ++t) {
    const TrialView trial = trial_view(map, test, generator, t, options.seed, options.data_name);
    SessionViewSpec spec;
    spec.title = trial.title;
    spec.source = trial.source;
    spec.map_name = options.map_name;
    spec.options = options.recognizer;
    const nlohmann::json data = session_view_data(map, &test.scene, trial.readings, trial.truth, spec);
    if (t == 0)  // the same scene for every trial: say it once
      for (const auto& w : data["warnings"])
        std::fprintf(stderr, "sva eval --html: %s\n", w.get<std::string>().c_str());
    write_session_page(dir / page_name(t), data);
    progress.advance();
  }
  progress.finish();
  io::write_text_file(dir / "index.html", index_page(result, worst_first(result), 10));
  return result.trials.size();
}

}  // namespace sva::view
