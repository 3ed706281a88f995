// Helpers shared by the fuzz entries (fuzz_detect.cc, fuzz_detect_cpu.cc): the byte reader, the
// abort on a broken invariant, the option edits and the checks every ok result must pass.
#pragma once

#include <cstddef>
#include <cstdint>

#include "ellipsekit/detector.h"

namespace ellipsekit::fuzz {

// Reads the fuzz input front to back; bytes past the end read as 0.
class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t U8() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint16_t U16() {
    const std::uint16_t lo = U8();
    return static_cast<std::uint16_t>(lo | (U8() << 8));
  }
  std::int16_t S16() { return static_cast<std::int16_t>(U16()); }
  const std::uint8_t* rest() const { return data_ + pos_; }
  std::size_t rest_size() const { return pos_ < size_ ? size_ - pos_ : 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Prints the broken invariant and the status that goes with it, then aborts (the fuzzer or the
// replay reports it).
[[noreturn]] void Fail(const char* what, const Status& st);

// Sets one option (field % 30) from a raw value; many of the values are out of range on purpose.
// Covers the edge, curve, arc, grouping, validation and cap fields and the enumerations (out-of-
// range enumerators too, backend included).
void EditOption(int field, int v, Options* o);

// The fields EditOption leaves alone (field % 15): the later additions to the validation
// (pair candidates, edge coverage, exclusive support, b/a floor, outer rims, refits, the second
// chance) and the crowd pass. Out-of-range and non-finite values too.
void EditOptionMore(int field, int v, Options* o);

// The view a harness hands detect(): a null data pointer when asked (null_data); `never_read` (any
// non-null pointer, which detect() must refuse before touching) when the geometry is not sane;
// else `pixels`.
ImageView FuzzView(const std::uint8_t* pixels, const std::uint8_t* never_read, bool null_data, bool sane_geometry,
                   int w, int h, std::ptrdiff_t stride);

// Aborts unless an ok result of a frame of w x h pixels under options `o` is consistent: counts
// within their bounds and caps, known cap flags, every ellipse finite with a >= b > 0 and theta in
// [-pi/2, pi/2), timings not negative.
void CheckResult(const DetectionResult& r, int w, int h, const Options& o);

// Aborts unless `got` (another backend's ok result for the same frame and options) has the same
// ellipses as the scalar `reference`, bit for bit, and the same edge pixel, curve and arc counts.
void CheckSameAsReference(const DetectionResult& reference, const DetectionResult& got);

}  // namespace ellipsekit::fuzz
