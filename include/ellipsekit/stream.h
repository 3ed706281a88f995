// Frame streams: the pixel stage of the next frame overlaps the back end of this one.
//
// A camera loop asks for frames per second at a bounded latency, not for one call's time. A
// Stream owns `depth` Detectors (one per frame in flight) and a worker thread. submit() copies a
// frame into a free slot and queues its pixel stage (edges, curves, arcs: on the Vulkan device
// for Backend::kVulkan, else on the CPU kernels) on the worker; wait() / poll() hand back the
// oldest frame's result, running its back end (grouping to the final ellipses) on the calling
// thread meanwhile the worker runs the next frame's pixel stage. Results come in submission order
// and are the ellipses detect() gives on the same frame (tests/test_stream.cc).
//
// Frames have the size given at creation; every buffer is sized then (a first detection on a
// blank frame), and grows afterwards only as detect()'s do, for a frame busier than any before.
// One thread at a time may call a Stream's methods.
#pragma once

#include <cstdint>
#include <memory>

#include "ellipsekit/detector.h"

namespace ellipsekit {

struct StreamResult {
  std::uint64_t tag = 0;   // as given to submit()
  Status status;           // the frame's outcome (what detect() would have returned)
  DetectionResult result;  // valid when status is ok
  double latency_ms = 0;   // from submit() to the result being ready
};

class Stream {
 public:
  static constexpr int kMaxDepth = 8;

  // depth: frames in flight, 1..kMaxDepth (2 overlaps the two stages; 3 absorbs jitter).
  Stream(const Options& options, int width, int height, int depth = 2);
  ~Stream();  // waits for the pixel stage in progress; results not yet taken are dropped
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  // Options, size and depth are checked here; an invalid set makes every call return that error.
  Status status() const;
  int depth() const;
  int in_flight() const;  // submitted and not yet returned by wait() / poll()

  // Copies `frame` (width x height as created) and queues it. An error, and nothing queued, for
  // a frame of another size or a bad view, or when depth() frames are already in flight.
  Status submit(const ImageView& frame, std::uint64_t tag);
  // The oldest frame's result, blocking until its pixel stage is done; an error when nothing is
  // in flight (the frame's own outcome is out->status). *out's vectors keep their capacity:
  // reuse one StreamResult, and later results allocate nothing.
  Status wait(StreamResult* out);
  // Like wait(), but false at once when nothing is in flight or the oldest frame's pixel stage
  // is not done yet; true when *out holds its result.
  bool poll(StreamResult* out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ellipsekit
