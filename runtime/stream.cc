// Stream (include/ellipsekit/stream.h): a ring of `depth` slots, each a Detector and a copy of its
// frame. The worker thread runs the pixel stage of submitted slots in order; wait() / poll() run
// the back end of the oldest slot on the calling thread. A slot is touched by one thread at a time:
// the caller while copying a frame into it (free slot) and while running its back end (its pixel
// stage done), the worker while running its pixel stage; the mutex orders the hand-overs.
#include "ellipsekit/stream.h"

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "runtime/detector_impl.h"

namespace ellipsekit {

namespace {

using Clock = std::chrono::steady_clock;

Status Invalid(const std::string& what) { return {StatusCode::kInvalidArgument, what}; }

// Runs f, turning an exception (allocation failure on a frame busier than any before) into a status.
template <typename F>
Status Guarded(F&& f) {
  try {
    return f();
  } catch (const std::exception& e) {
    return {StatusCode::kInternal, std::string("detect failed: ") + e.what()};
  }
}

}  // namespace

struct Stream::Impl {
  struct Slot {
    std::unique_ptr<Detector> detector;
    std::vector<std::uint8_t> pixels;  // the frame, width x height, stride width
    std::uint64_t tag = 0;
    Clock::time_point submitted;
    Status pixel_status;
    bool pixel_done = false;
  };

  Status status;
  int width = 0, height = 0, depth = 0;
  std::vector<Slot> slots;
  int head = 0;      // the oldest slot in flight
  int count = 0;     // slots in flight
  int next_pixel = 0;  // the next slot whose pixel stage the worker runs
  int queued = 0;    // slots submitted whose pixel stage has not started
  bool stop = false;
  std::mutex mutex;
  std::condition_variable work, done;
  std::thread worker;

  ImageView View(const Slot& s) const { return {s.pixels.data(), width, height, width}; }

  void Work() {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      work.wait(lock, [this] { return stop || queued > 0; });
      if (stop) return;
      Slot& s = slots[static_cast<std::size_t>(next_pixel)];
      --queued;
      lock.unlock();
      const Status st = Guarded([&] { return s.detector->impl_->PixelStage(View(s)); });
      lock.lock();
      s.pixel_status = st;
      s.pixel_done = true;
      next_pixel = (next_pixel + 1) % depth;
      done.notify_all();
    }
  }

  // The back end of the oldest slot, whose pixel stage is done; then the slot is free.
  void Finish(StreamResult* out) {
    Slot& s = slots[static_cast<std::size_t>(head)];
    out->tag = s.tag;
    out->status = s.pixel_status;
    if (out->status.ok()) {
      out->status = Guarded([&] { return s.detector->impl_->BackEnd(&out->result); });
    }
    out->latency_ms = std::chrono::duration<double, std::milli>(Clock::now() - s.submitted).count();
    std::lock_guard<std::mutex> lock(mutex);
    s.pixel_done = false;
    head = (head + 1) % depth;
    --count;
  }
};

Stream::Stream(const Options& options, int width, int height, int depth) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.width = width;
  m.height = height;
  m.depth = depth;
  if (depth < 1 || depth > kMaxDepth) {
    m.status = Invalid("stream depth " + std::to_string(depth) + " is not in [1, " + std::to_string(kMaxDepth) + "]");
    return;
  }
  m.slots.resize(static_cast<std::size_t>(depth));
  for (Impl::Slot& s : m.slots) {
    s.detector = std::make_unique<Detector>(options);
    if (m.status = s.detector->status(); !m.status.ok()) return;
    s.pixels.assign(static_cast<std::size_t>(std::max(width, 0)) * std::max(height, 0), 0);
    if (m.status = ValidateImage(m.View(s), options); !m.status.ok()) return;
    // Sizes every buffer of the slot (and creates the coarse levels' Detectors) up front.
    DetectionResult blank;
    if (m.status = s.detector->detect(m.View(s), &blank); !m.status.ok()) return;
  }
  m.worker = std::thread([&m] { m.Work(); });
}

Stream::~Stream() {
  if (!impl_ || !impl_->worker.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stop = true;
  }
  impl_->work.notify_all();
  impl_->worker.join();
}

Status Stream::status() const { return impl_->status; }
int Stream::depth() const { return impl_->depth; }

int Stream::in_flight() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->count;
}

Status Stream::submit(const ImageView& frame, std::uint64_t tag) {
  Impl& m = *impl_;
  if (!m.status.ok()) return m.status;
  if (frame.width != m.width || frame.height != m.height)
    return Invalid("frame size " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                   " differs from the stream's " + std::to_string(m.width) + "x" + std::to_string(m.height));
  if (Status st = ValidateImage(frame, m.slots.front().detector->options()); !st.ok()) return st;
  int index = 0;
  {
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.count == m.depth)
      return Invalid("stream full: " + std::to_string(m.depth) + " frames in flight; take one with wait() first");
    index = (m.head + m.count) % m.depth;
  }
  Impl::Slot& s = m.slots[static_cast<std::size_t>(index)];  // free: no thread touches it
  for (int y = 0; y < m.height; ++y)
    std::memcpy(s.pixels.data() + static_cast<std::size_t>(y) * m.width, frame.data + y * frame.stride,
                static_cast<std::size_t>(m.width));
  s.tag = tag;
  s.submitted = Clock::now();
  {
    std::lock_guard<std::mutex> lock(m.mutex);
    ++m.count;
    ++m.queued;
  }
  m.work.notify_one();
  return Status::Ok();
}

Status Stream::wait(StreamResult* out) {
  Impl& m = *impl_;
  if (out == nullptr) return Invalid("result is null");
  if (!m.status.ok()) return m.status;
  {
    std::unique_lock<std::mutex> lock(m.mutex);
    if (m.count == 0) return Invalid("nothing in flight: submit() a frame first");
    m.done.wait(lock, [&m] { return m.slots[static_cast<std::size_t>(m.head)].pixel_done; });
  }
  m.Finish(out);
  return Status::Ok();
}

bool Stream::poll(StreamResult* out) {
  Impl& m = *impl_;
  if (out == nullptr || !m.status.ok()) return false;
  {
    std::lock_guard<std::mutex> lock(m.mutex);
    if (m.count == 0 || !m.slots[static_cast<std::size_t>(m.head)].pixel_done) return false;
  }
  m.Finish(out);
  return true;
}

}  // namespace ellipsekit
