#include "args.hpp"
namespace sva::cli {
int cmd_bench(const std::vector<std::string>&) { throw Error("sva bench: being built (skeleton)"); }
}  // namespace sva::cli
