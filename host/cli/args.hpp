#pragma once
// Minimal declarative argument parsing for the sva subcommands: options are
// declared with their help text, then parsed; unknown options, missing values
// and malformed numbers are reported as sva::Error naming the option.
#include <sva/error.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace sva::cli {

class Args {
 public:
  Args(std::string command, std::string summary, std::vector<std::string> argv);
  // An option taking a value. `repeatable` options may appear several times.
  Args& option(const std::string& name, const std::string& metavar, const std::string& help, bool repeatable = false);
  Args& flag(const std::string& name, const std::string& help);
  // Parses; returns false when --help was requested (help already printed).
  bool parse();

  bool has(const std::string& name) const;
  std::optional<std::string> get(const std::string& name) const;
  std::string get_or(const std::string& name, const std::string& fallback) const;
  std::string required(const std::string& name) const;
  std::vector<std::string> all(const std::string& name) const;
  long long integer(const std::string& name, long long fallback, long long lo, long long hi) const;
  double number(const std::string& name, double fallback, double lo, double hi) const;
  // An on|off option (absent: `fallback`).
  bool on_off(const std::string& name, bool fallback) const;
  void print_help() const;

 private:
  struct Spec {
    std::string name, metavar, help;
    bool takes_value, repeatable;
  };
  std::string command_, summary_;
  std::vector<std::string> argv_;
  std::vector<Spec> specs_;
  std::map<std::string, std::vector<std::string>> values_;
};

// Subcommands: each lives in its own cmd_*.cpp.
int cmd_simulate(const std::vector<std::string>& args);
int cmd_inspect(const std::vector<std::string>& args);
int cmd_export(const std::vector<std::string>& args);
int cmd_demo(const std::vector<std::string>& args);
int cmd_train(const std::vector<std::string>& args);
int cmd_eval(const std::vector<std::string>& args);
int cmd_recognize(const std::vector<std::string>& args);
int cmd_bench(const std::vector<std::string>& args);
int cmd_record(const std::vector<std::string>& args);
int cmd_live(const std::vector<std::string>& args);
int cmd_calibrate(const std::vector<std::string>& args);
int cmd_replay(const std::vector<std::string>& args);
int cmd_view(const std::vector<std::string>& args);

}  // namespace sva::cli
