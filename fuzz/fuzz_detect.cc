// Input layout (all little-endian, missing bytes read as 0):
//   byte 0      shape selector: low 2 bits pick the size family (small, thin row, thin column,
//               tiny); bit 2 gives a stride smaller than the width; bit 3 a null data pointer;
//               bit 4 a zero/negative size; bit 5 also runs the Vulkan backend (slow: lavapipe)
//   bytes 1-4   width and height seeds (u16 each)
//   byte 5      extra stride padding
//   byte 6      number of option edits that follow (mod 8)
//   3 bytes per option edit: field index, then a signed 16-bit value (raw, may be out of range)
//   the rest    pixels, repeated to fill the frame (all zero when none are left)
// The pixel buffer is allocated to exactly (height - 1) * stride + width bytes, so a read past the
// last pixel of the view is caught by AddressSanitizer.
#include "fuzz/fuzz_detect.h"

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <vector>

#include "ellipsekit/detector.h"
#include "fuzz/fuzz_common.h"

namespace ellipsekit::fuzz {

int DetectOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  const std::uint8_t shape = in.U8();
  const int ws = in.U16(), hs = in.U16();
  int w = 0, h = 0;
  switch (shape & 3) {
    case 0: w = 1 + ws % 160; h = 1 + hs % 160; break;   // small frames
    case 1: w = 1 + ws % 16400; h = 1 + hs % 3; break;   // thin rows, past the 16384 px limit
    case 2: w = 1 + ws % 3; h = 1 + hs % 16400; break;   // thin columns
    default: w = 1 + ws % 8; h = 1 + hs % 8; break;      // tiny
  }
  if (shape & 0x10) {  // a non-positive size from the seeds
    if (ws & 1) w = -static_cast<int>(ws % 4); else h = -static_cast<int>(hs % 4);
  }
  std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(w) + in.U8() % 17;
  if (shape & 0x04) stride = static_cast<std::ptrdiff_t>(w) - 1 - (ws % 3);

  Options options;
  const int edits = in.U8() % 8;
  for (int i = 0; i < edits; ++i) {
    const int field = in.U8();
    EditOption(field, in.S16(), &options);
  }

  // The pixels: exactly the bytes the view covers, no slack.
  std::vector<std::uint8_t> pixels;
  const bool sane_geometry = w > 0 && h > 0 && stride >= w;
  if (sane_geometry) {
    pixels.resize(static_cast<std::size_t>(h - 1) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(w));
    const std::uint8_t* src = in.rest();
    const std::size_t n = in.rest_size();
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = n ? src[i % n] : 0;
  }
  // A heap copy of exactly the right size keeps the buffer end where ASan can see it.
  std::unique_ptr<std::uint8_t[]> buffer;
  if (!pixels.empty()) {
    buffer = std::make_unique<std::uint8_t[]>(pixels.size());
    std::copy(pixels.begin(), pixels.end(), buffer.get());
  }
  const ImageView view = FuzzView(buffer.get(), data, (shape & 0x08) != 0, sane_geometry, w, h, stride);

  const Status options_ok = ValidateOptions(options);
  const Status image_ok = options_ok.ok() ? ValidateImage(view, options) : options_ok;

  std::vector<Backend> backends = {Backend::kScalar, Backend::kSimd, Backend::kAuto};
  // ELLIPSEKIT_FUZZ_NO_VULKAN=1 leaves Vulkan out (for leak-checking runs: see scripts/fuzz.sh).
  static const bool no_vulkan = [] {
    const char* v = std::getenv("ELLIPSEKIT_FUZZ_NO_VULKAN");
    return v != nullptr && v[0] == '1';
  }();
  if ((shape & 0x20) && !no_vulkan) backends.push_back(Backend::kVulkan);
  DetectionResult result;
  // The scalar reference's ok result, which every other backend must equal (DESIGN.md "Backends agree").
  DetectionResult reference;
  bool have_reference = false;
  for (Backend b : backends) {
    Options o = options;
    if (options.backend == Backend::kScalar || options.backend == Backend::kSimd ||
        options.backend == Backend::kAuto || options.backend == Backend::kVulkan)
      o.backend = b;  // an out-of-range enumerator is kept: it must be refused
    Detector det(o);
    const Status ds = det.status();
    if (!ds.ok()) {
      if (ds.code() == StatusCode::kUnavailable && (b == Backend::kSimd || b == Backend::kVulkan)) continue;
      if (options_ok.ok() && b == Backend::kScalar) Fail("scalar detector refused valid options", ds);
      if (ds.message().empty()) Fail("error status without a message", ds);
      const Status st = det.detect(view, &result);
      if (st.ok()) Fail("detect() ok on a detector whose status is an error", st);
      continue;
    }
    if (!options_ok.ok()) Fail("detector accepted invalid options", options_ok);
    for (int run = 0; run < 2; ++run) {  // the second run reuses the buffers
      const Status st = det.detect(view, &result);
      // A valid frame may be refused only by Vulkan, and only as unavailable (say, a frame larger
      // than the device allows); any other error there is a bug like on the CPU backends.
      if (image_ok.ok() && !st.ok() && !(b == Backend::kVulkan && st.code() == StatusCode::kUnavailable))
        Fail("detect() refused a valid image", st);
      if (!image_ok.ok()) {
        if (st.ok()) Fail("detect() accepted an invalid image", image_ok);
        if (st.message().empty()) Fail("error status without a message", st);
        break;
      }
      if (!st.ok()) break;
      CheckResult(result, w, h, o);
      if (b == Backend::kScalar) {
        if (run == 0) {
          reference = result;
          have_reference = true;
        }
      } else if (have_reference) {
        CheckSameAsReference(reference, result);
      }
    }
  }
  return 0;
}

}  // namespace ellipsekit::fuzz
