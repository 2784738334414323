#pragma once
// Transparent huge pages for malloc in the processes whose grids are large (robot agent, offline
// SLAM). glibc >= 2.35 with THP mode "madvise": a 4 KiB page fault costs ~5 us in these VMs and the
// submap and branch-and-bound grids touch ~200 MB (MIT CSAIL: 45 k -> 5-10 k page faults, ~-12 %
// SLAM CPU, bit-identical results, +3-13 MB peak RSS). GLIBC_TUNABLES is read only at start-up, so
// the program is re-executed once with it set; a GLIBC_TUNABLES already set (or CAIRN_NO_THP) is
// respected. Call first thing in main.

namespace cairn {

void reexec_with_huge_pages(char** argv);

}  // namespace cairn
