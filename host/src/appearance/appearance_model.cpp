// Skeleton: replaced by the descriptor, normConf and soft-class implementations.
#include "appearance/appearance_model.hpp"

#include <sva/error.hpp>

namespace sva {

std::vector<BinWeight> DistanceBins::bins(double) const { throw Error("distance bins: being built (skeleton)"); }
std::vector<float> AppearanceModel::describe(const Reading&) const { throw Error("describe: being built (skeleton)"); }
std::vector<ClassWeight> AppearanceModel::classify(const std::vector<float>&) const { throw Error("classify: being built (skeleton)"); }
float AppearanceModel::norm_conf(const Reading&) const { throw Error("norm_conf: being built (skeleton)"); }

}  // namespace sva
