#include "args.hpp"
namespace sva::cli {
int cmd_export(const std::vector<std::string>&) { throw Error("sva export: being built (skeleton)"); }
}  // namespace sva::cli
