#include "tools/cli/args.h"

#include "tools/cli/json.h"

#include <cerrno>
#include <cstdlib>

#include "ellipsekit/detector.h"

namespace ellipsekit::cli {

bool ArgReader::Next() {
  while (next_ < args_.size()) {
    const std::string& arg = args_[next_++];
    has_inline_ = false;
    inline_value_.clear();
    if (!options_ended_ && arg == "--") {
      options_ended_ = true;
      continue;
    }
    is_flag_ = !options_ended_ && arg.size() > 1 && arg[0] == '-';
    name_ = arg;
    if (is_flag_ && arg.rfind("--", 0) == 0) {
      if (const auto eq = arg.find('='); eq != std::string::npos) {
        name_ = arg.substr(0, eq);
        inline_value_ = arg.substr(eq + 1);
        has_inline_ = true;
      }
    }
    return true;
  }
  return false;
}

std::string ArgReader::Value() {
  if (has_inline_) return inline_value_;
  if (next_ >= args_.size()) throw UsageError(name_ + " needs a value");
  return args_[next_++];
}

void ArgReader::NoValue() const {
  if (has_inline_) throw UsageError(name_ + " takes no value");
}

int ParseIntValue(const std::string& flag, const std::string& text, int min_value, int max_value) {
  const std::string range = "an integer in [" + std::to_string(min_value) + ", " +
                            std::to_string(max_value) + "]";
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || value < min_value || value > max_value) {
    throw UsageError(flag + ": bad value '" + text + "': expected " + range);
  }
  return static_cast<int>(value);
}

std::uint64_t ParseUint64Value(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] == '-' || text[0] == '+' || *end != '\0' || errno == ERANGE) {
    throw UsageError(flag + ": bad value '" + text + "': expected an unsigned 64-bit integer");
  }
  return static_cast<std::uint64_t>(value);
}

double ParseDoubleValue(const std::string& flag, const std::string& text, double min_value, double max_value) {
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !(value >= min_value && value <= max_value)) {
    throw UsageError(flag + ": bad value '" + text + "': expected a number in [" + JsonNumber(min_value, 3) + ", " +
                     JsonNumber(max_value, 3) + "]");
  }
  return value;
}

Backend ParseBackendValue(const std::string& flag, const std::string& text) {
  Backend backend = Backend::kAuto;
  if (!ParseBackend(text.c_str(), &backend)) {
    throw UsageError(flag + ": bad value '" + text + "': expected auto, scalar, simd or vulkan");
  }
  return backend;
}

bool ApplyDetectorFlag(const std::string& name, ArgReader* reader, Options* options) {
  if (name == "--backend") {
    options->backend = ParseBackendValue(name, reader->Value());
    return true;
  }
  if (name == "--option") {
    const Status st = SetOption(reader->Value(), options);
    if (!st.ok()) throw UsageError(name + ": " + st.message());
    return true;
  }
  return false;
}

}  // namespace ellipsekit::cli
