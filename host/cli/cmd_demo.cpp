#include "args.hpp"
namespace sva::cli {
int cmd_demo(const std::vector<std::string>&) { throw Error("sva demo: being built (skeleton)"); }
}  // namespace sva::cli
