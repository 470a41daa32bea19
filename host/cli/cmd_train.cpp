#include "args.hpp"
namespace sva::cli {
int cmd_train(const std::vector<std::string>&) { throw Error("sva train: being built (skeleton)"); }
}  // namespace sva::cli
