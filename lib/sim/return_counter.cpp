#include "sim/return_counter.h"

namespace evade::sim {

void ReturnCounter::reach(int64_t revolution) {
  if (revolution <= current_) return;
  complete_ = revolution == current_ + 1 ? counting_ : std::vector<int32_t>{};  // a skipped revolution saw nothing
  any_complete_ = true;
  counting_.clear();
  current_ = revolution;
}

void ReturnCounter::add(int64_t revolution, size_t index) {
  reach(revolution);
  if (revolution < current_) return;  // a late return of a closed revolution is not counted
  if (counting_.size() <= index) counting_.resize(index + 1, 0);
  ++counting_[index];
}

std::vector<int32_t> ReturnCounter::last_complete(size_t solids) const {
  if (!any_complete_) return std::vector<int32_t>(solids, -1);
  std::vector<int32_t> out(solids, 0);
  for (size_t i = 0; i < solids && i < complete_.size(); ++i) out[i] = complete_[i];
  return out;
}

}  // namespace evade::sim
