#pragma once
// Recorder: records while something else runs — `vifusion record` on a live camera, vifusiond while it
// maps (`record: true`). Producers on their own threads hand over frames, IMU samples, sync edges and
// clock mappings through fixed-capacity rings; the recorder's thread serialises them into a RecordingFile
// and writes chunks on the time budget (chunk_flush_ns, 50 ms by default). What a kill can cost: an item
// handed over at t is in the file by t + chunk_flush_ns + idle_wait_ns + the write itself (a few ms), so
// the newest item of a killed recording is at most that, plus the gap between the producers' hand-overs
// (one frame period, 33 ms at 30 Hz), before the kill: within 100 ms at the defaults.
//
// A producer never waits and never allocates: push*() copies into a pre-sized ring slot and returns false
// when the ring is full (the item is lost and counted) or the recording has ended. A write failure (disk
// full, storage unplugged, I/O error) ends the recording: the file keeps everything up to its last complete
// chunk, error() says what happened, and the pushes that follow are counted as lost, so the producers (the
// SLAM thread among them) carry on unaffected.
//
// Threads: one producer thread per push function (each ring is single-producer), any thread for stats(),
// the owner for stop().

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>
#include <thread>

#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/motion/packet_format.hpp"
#include "vifusion/recording/recording_file.hpp"

namespace vifusion::recording {

struct RecorderOptions {
  /// Frames waiting to be written, [1, 256]: 8 hold a quarter of a second at 30 Hz while the disk stalls
  /// (1.5 MB each at 640×480, allocated once).
  std::size_t frame_ring = 8;
  std::size_t imu_ring = 4096;   ///< IMU samples waiting, [1, 1 << 20]: 20 s at 200 Hz
  std::size_t edge_ring = 1024;  ///< sync-line edges waiting, [1, 1 << 20]
  std::size_t clock_ring = 256;  ///< clock mappings waiting, [1, 1 << 20]
  /// Motion-module transfers waiting, [1, 1 << 16]: 512 is ≈5 s of the module's ≈100 transfers/s (1 KiB each).
  std::size_t motion_ring = 512;
  /// How long the recorder's thread sleeps when every ring is empty [ns], (0, 100 ms]: far below
  /// chunk_flush_ns, so chunks are written on time.
  std::int64_t idle_wait_ns = 2'000'000;
  mcap::McapWriterOptions mcap;

  /// @throws vifusion::Error naming the bad field.
  void validate() const;
};

struct RecorderStats {
  bool recording = false;            ///< false once stopped or failed
  bool failed = false;               ///< a write failed: the recording ended early
  std::string error;                 ///< what failed (path, offset, errno text); empty when nothing did
  RecordingCounts written;           ///< items serialised into the file
  std::uint64_t frames_dropped = 0;  ///< pushes refused because the ring was full or the recording had ended
  std::uint64_t imu_dropped = 0;
  std::uint64_t edges_dropped = 0;
  std::uint64_t motion_dropped = 0;
  std::uint64_t clocks_dropped = 0;
  std::uint64_t bytes_written = 0;       ///< file size so far
  std::uint64_t messages_in_chunks = 0;  ///< messages a reader finds if the recording stops now
  /// CPU time the recorder's thread has used [ns], as of its latest pass (serialising, writing, fdatasync
  /// calls; the final drain and close in stop() run on the caller's thread and are not in it).
  std::int64_t thread_cpu_ns = 0;
};

class Recorder {
 public:
  /// Opens `path` and starts the recorder's thread. `header.calibration` sizes the frame slots.
  /// @throws vifusion::Error when the file cannot be created (naming it and why) or the options are bad.
  Recorder(const std::filesystem::path& path, const RecordingHeader& header, const RecorderOptions& options = {});
  /// stop().
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  bool pushFrame(const RgbdFrame& frame);
  /// True when the next pushFrame() would find no free slot (the producer's view: never understated).
  bool frameRingFull() const { return frames_.size() == frames_.capacity(); }
  bool pushImu(const ImuSample& sample);
  bool pushSyncEdge(std::int64_t t_ns, bool rising, std::uint64_t sequence);
  bool pushClock(const ClockRecord& clock);
  /// One motion-module transfer as received (bytes beyond motion::kMaxTransferBytes are not kept).
  bool pushMotionTransfer(std::int64_t host_receive_ns, std::uint32_t index, std::span<const std::uint8_t> bytes);

  /// Writes what the rings hold, completes the file (summary) and ends the thread; idempotent.
  /// @return false when the recording failed at any point (stats().error says why).
  bool stop();
  RecorderStats stats() const;
  const std::filesystem::path& path() const { return path_; }

 private:
  struct MotionTransferItem {
    std::int64_t host_receive_ns = 0;
    std::uint32_t index = 0;
    std::size_t size = 0;
    std::array<std::uint8_t, motion::kMaxTransferBytes> bytes{};
  };
  struct SyncEdgeItem {
    std::int64_t t_ns = 0;
    bool rising = true;
    std::uint64_t sequence = 0;
  };

  void run();
  /// Writes (or, after a failure, discards) everything waiting; true when anything was waiting.
  bool drain();
  void noteFailure();

  std::filesystem::path path_;
  RecorderOptions options_;
  RecordingFile file_;
  SpscRing<RgbdFrame> frames_;
  SpscRing<ImuSample> imu_;
  SpscRing<SyncEdgeItem> edges_;
  SpscRing<MotionTransferItem> motion_;
  MotionTransferItem motion_item_;  ///< the producer's staging slot
  SpscRing<ClockRecord> clocks_;
  std::atomic<bool> accepting_{true};  ///< false once stopped or failed: pushes are counted as lost
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> frames_lost_{0}, imu_lost_{0}, edges_lost_{0}, clocks_lost_{0}, motion_lost_{0};
  bool stopped_ = false;
  bool closed_ok_ = true;
  mutable std::mutex stats_mutex_;  ///< guards the snapshot below (the thread updates it after each drain)
  RecorderStats snapshot_;
  std::thread thread_;
};

}  // namespace vifusion::recording
