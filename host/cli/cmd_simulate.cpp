#include "args.hpp"
namespace sva::cli {
int cmd_simulate(const std::vector<std::string>&) { throw Error("sva simulate: being built (skeleton)"); }
}  // namespace sva::cli
