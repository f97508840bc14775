#pragma once
// vifusiond's map file writer (config map_file): the SLAM thread captures the map into this saver's snapshot
// between two frames (slam::captureMap: the readback, ≈ the cost of one rt/vifusion/map export), and this
// saver's own thread encodes, writes, syncs and renames it while the SLAM thread goes on with the next frames.
// One snapshot: while a write is in progress the next save waits for it (the SLAM thread asks idle() and tries
// again after the next frame), so a slow disk delays saves, never frames.
//
// Every write, successful or not, is counted in SharedState (map_saves, map_save_failures, the last file's
// size, capture and write times) and logged; a failed write leaves the file at the path as it was
// (mapfile::MapFileWriter writes a temporary file and renames it).

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/slam/map_saving.hpp"

namespace vifusion::daemon {

class MapSaver {
 public:
  /// Reserves the snapshot for `surfel_capacity` surfels and `frames` poses, and starts the writer thread.
  MapSaver(std::string path, std::uint32_t surfel_capacity, std::size_t frames, SharedState& state);
  /// Finishes a write in progress, then stops the thread.
  ~MapSaver();
  MapSaver(const MapSaver&) = delete;
  MapSaver& operator=(const MapSaver&) = delete;

  /// No write in progress: snapshot() may be filled and write() called.
  bool idle() const;
  /// The snapshot to capture into; only while idle(), and only from the thread that calls write().
  slam::MapSnapshot& snapshot() { return snapshot_; }
  /// Hands the captured snapshot to the writer thread. `request_id`: the rt/vifusion/map_save_request this save
  /// answers (SharedState::map_save_request_done once written), 0 for none.
  void write(std::uint64_t request_id);
  /// Blocks until no write is in progress. @returns whether the last write succeeded (true before any).
  bool waitIdle();

  const std::string& path() const { return path_; }

 private:
  void run();
  void writeSnapshot(std::uint64_t request_id);

  std::string path_;
  SharedState& state_;
  slam::MapSnapshot snapshot_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool pending_ = false;  ///< a snapshot waits for, or is in, the write
  bool quit_ = false;
  bool last_ok_ = true;
  std::uint64_t request_id_ = 0;
  std::thread thread_;  ///< last: starts once everything it uses exists
};

}  // namespace vifusion::daemon
