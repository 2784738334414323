#include "common/huge_pages.h"

#include <unistd.h>

#include <cstdlib>

namespace cairn {

void reexec_with_huge_pages(char** argv) {
  if (std::getenv("GLIBC_TUNABLES") != nullptr || std::getenv("CAIRN_NO_THP") != nullptr) return;
  if (setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: run as is
  unsetenv("GLIBC_TUNABLES");
}

}  // namespace cairn
