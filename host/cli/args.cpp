#include "args.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>

namespace sva::cli {

Args::Args(std::string command, std::string summary, std::vector<std::string> argv)
    : command_(std::move(command)), summary_(std::move(summary)), argv_(std::move(argv)) {}

Args& Args::option(const std::string& name, const std::string& metavar, const std::string& help, bool repeatable) {
  specs_.push_back({name, metavar, help, true, repeatable});
  return *this;
}
Args& Args::flag(const std::string& name, const std::string& help) {
  specs_.push_back({name, "", help, false, false});
  return *this;
}

bool Args::parse() {
  for (std::size_t i = 0; i < argv_.size(); ++i) {
    std::string a = argv_[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return false;
    }
    std::string value;
    bool inline_value = false;
    if (auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = a.substr(eq + 1);
      a = a.substr(0, eq);
      inline_value = true;
    }
    const Spec* spec = nullptr;
    for (const auto& s : specs_)
      if (s.name == a) spec = &s;
    if (!spec) {
      if (a.rfind("-", 0) == 0) throw Error(command_ + ": unknown option " + a + " (see " + command_ + " --help)");
      throw Error(command_ + ": unexpected argument \"" + a + "\" (see " + command_ + " --help)");
    }
    if (spec->takes_value) {
      if (!inline_value) {
        if (i + 1 >= argv_.size()) throw Error(command_ + ": option " + a + " needs a value " + spec->metavar);
        value = argv_[++i];
      }
      auto& v = values_[a];
      if (!v.empty() && !spec->repeatable) throw Error(command_ + ": option " + a + " given more than once");
      v.push_back(value);
    } else {
      if (inline_value) throw Error(command_ + ": option " + a + " takes no value");
      values_[a].push_back("1");
    }
  }
  return true;
}

bool Args::has(const std::string& name) const { return values_.count(name) > 0; }
std::optional<std::string> Args::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second.back();
}
std::string Args::get_or(const std::string& name, const std::string& fallback) const {
  return get(name).value_or(fallback);
}
std::string Args::required(const std::string& name) const {
  auto v = get(name);
  if (!v || v->empty()) throw Error(command_ + ": missing required option " + name + " (see " + command_ + " --help)");
  return *v;
}
std::vector<std::string> Args::all(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

long long Args::integer(const std::string& name, long long fallback, long long lo, long long hi) const {
  auto v = get(name);
  if (!v) return fallback;
  errno = 0;
  char* end = nullptr;
  long long x = std::strtoll(v->c_str(), &end, 10);
  if (v->empty() || *end != '\0' || errno == ERANGE)
    throw Error(command_ + ": " + name + " expects an integer, got \"" + *v + "\"");
  if (x < lo || x > hi)
    throw Error(command_ + ": " + name + " " + *v + " is out of range [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
  return x;
}

double Args::number(const std::string& name, double fallback, double lo, double hi) const {
  auto v = get(name);
  if (!v) return fallback;
  char* end = nullptr;
  double x = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0' || !std::isfinite(x))
    throw Error(command_ + ": " + name + " expects a finite number, got \"" + *v + "\"");
  if (x < lo || x > hi) {
    std::ostringstream range;  // 10 digits: a bound just below 1 is not shown as 1
    range << std::setprecision(10) << "[" << lo << ", " << hi << "]";
    throw Error(command_ + ": " + name + " " + *v + " is out of range " + range.str());
  }
  return x;
}

bool Args::on_off(const std::string& name, bool fallback) const {
  auto v = get(name);
  if (!v) return fallback;
  if (*v == "on") return true;
  if (*v == "off") return false;
  throw Error(command_ + ": " + name + " expects on or off, got \"" + *v + "\"");
}

void Args::print_help() const {
  std::printf("usage: %s [options]\n\n%s\n\noptions:\n", command_.c_str(), summary_.c_str());
  for (const auto& s : specs_) {
    std::string left = "  " + s.name + (s.takes_value ? " " + s.metavar : "");
    if (left.size() < 30)
      left.resize(30, ' ');
    else
      left += "\n" + std::string(30, ' ');
    std::printf("%s%s%s\n", left.c_str(), s.help.c_str(), s.repeatable ? " (repeatable)" : "");
  }
  std::printf("  %-28s%s\n", "--help", "show this help");
}

}  // namespace sva::cli
