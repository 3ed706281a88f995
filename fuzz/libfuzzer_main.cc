// libFuzzer entry (clang -fsanitize=fuzzer): calls ELLIPSEKIT_FUZZ_ENTRY (fuzz_detect.h; default
// DetectOneInput, see fuzz_detect.cc for its input layout; fuzz_detect_cpu builds this file with
// DetectCpuOneInput, see fuzz_detect_cpu.cc).
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_detect.h"

#ifndef ELLIPSEKIT_FUZZ_ENTRY
#define ELLIPSEKIT_FUZZ_ENTRY DetectOneInput
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ellipsekit::fuzz::ELLIPSEKIT_FUZZ_ENTRY(data, size);
}
