#pragma once
// Error convention: loaders and parsers of files (world, config, logs, g2o) throw InputError with a
// message that names the file and the line or key; apps catch it at the top, print that one line
// and exit non-zero. Algorithm cores never throw: they return std::optional or result structs.
#include <stdexcept>
#include <string>

namespace cairn {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cairn
