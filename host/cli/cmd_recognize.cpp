#include "args.hpp"
namespace sva::cli {
int cmd_recognize(const std::vector<std::string>&) { throw Error("sva recognize: being built (skeleton)"); }
}  // namespace sva::cli
