#pragma once
// What every libFuzzer harness here shares: the decoders under test read files by path (as the
// binaries do), so each input is written to a file in a private temporary folder, removed at exit;
// CAIRN_FUZZ_SEEDS=<dir> asks a harness to write valid example inputs there (run_fuzzer.sh does),
// for decoders whose inputs no file in the repository or ../shared/data shows.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace cairn::fuzz {

class ScratchDir {
 public:
  ScratchDir() {
    char pattern[] = "/tmp/cairn-fuzz-XXXXXX";
    const char* made = mkdtemp(pattern);
    if (made == nullptr) std::abort();  // no temporary folder: nothing can be fuzzed
    path_ = made;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline const std::string& scratch_dir() {
  static const ScratchDir dir;
  return dir.path();
}

/// Writes `size` bytes to `dir`/`name` (replacing it) and returns the path.
inline std::string write_file(const std::string& dir, const std::string& name, const void* data, size_t size) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(static_cast<const char*>(data), std::streamsize(size));
  return path;
}

inline std::string write_input(const uint8_t* data, size_t size, const std::string& name) {
  return write_file(scratch_dir(), name, data, size);
}

/// The folder CAIRN_FUZZ_SEEDS names, or empty.
inline std::string seeds_dir() {
  const char* dir = std::getenv("CAIRN_FUZZ_SEEDS");
  return dir == nullptr ? std::string() : std::string(dir);
}

}  // namespace cairn::fuzz
