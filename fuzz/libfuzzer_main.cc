// libFuzzer entry (clang -fsanitize=fuzzer): see fuzz_detect.cc for the input layout.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_detect.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ellipsekit::fuzz::DetectOneInput(data, size);
}
