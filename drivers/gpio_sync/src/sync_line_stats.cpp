#include "vifusion/gpio_sync/sync_line_stats.hpp"

namespace vifusion::gpio_sync {

const char* syncLineStateName(SyncLineState state) {
  switch (state) {
    case SyncLineState::kClosed:
      return "closed";
    case SyncLineState::kRunning:
      return "running";
    case SyncLineState::kGone:
      return "gone";
    case SyncLineState::kFailed:
      return "failed";
  }
  return "invalid";
}

}  // namespace vifusion::gpio_sync
