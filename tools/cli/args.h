// Hand-rolled argument parsing shared by the subcommands.
//
// Flags are `--name VALUE` or `--name=VALUE`; `--` ends the flags; anything else is positional.
// A usage problem (unknown flag, missing or bad value) throws UsageError, which main() turns
// into one line on stderr and exit status 2.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ellipsekit/options.h"

namespace ellipsekit::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // a file or detection problem (reported, others went on)
inline constexpr int kExitUsage = 2;    // bad command line

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ArgReader {
 public:
  explicit ArgReader(std::vector<std::string> args) : args_(std::move(args)) {}

  // Moves to the next argument; false when none is left.
  bool Next();
  // The current argument is a flag (starts with '-' and is not "-" nor after "--").
  bool IsFlag() const { return is_flag_; }
  // The flag's name without any "=value" part, e.g. "--repeat".
  const std::string& name() const { return name_; }
  // The current positional argument.
  const std::string& positional() const { return name_; }
  // The flag's value: the "=value" part or the next argument. Throws when there is none.
  std::string Value();
  // Throws when a flag that takes no value was given one ("--per-image=1").
  void NoValue() const;

 private:
  std::vector<std::string> args_;
  std::size_t next_ = 0;
  bool options_ended_ = false;
  bool is_flag_ = false;
  bool has_inline_ = false;
  std::string name_, inline_value_;
};

// Value parsers: throw UsageError naming the flag and the accepted range.
int ParseIntValue(const std::string& flag, const std::string& text, int min_value, int max_value);
std::uint64_t ParseUint64Value(const std::string& flag, const std::string& text);
double ParseDoubleValue(const std::string& flag, const std::string& text, double min_value, double max_value);
Backend ParseBackendValue(const std::string& flag, const std::string& text);
// The detector flags shared by every command that detects: --backend B and --option NAME=VALUE
// (one ellipsekit::SetOption). Returns false when `name` is neither; throws UsageError on a bad value.
bool ApplyDetectorFlag(const std::string& name, ArgReader* reader, Options* options);

}  // namespace ellipsekit::cli
