#include "args.hpp"
namespace sva::cli {
int cmd_eval(const std::vector<std::string>&) { throw Error("sva eval: being built (skeleton)"); }
}  // namespace sva::cli
