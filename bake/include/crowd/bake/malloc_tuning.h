// glibc's allocator, set for a baker: freed memory is kept for the next allocation instead of
// going back to the kernel, and large blocks sit on transparent huge pages. By default glibc maps
// every block over 128 KiB on its own and trims its heap whenever 128 KiB at the top are free, so
// a bake that allocates and frees a frame's worth of buffers per time it samples took the same
// pages from the kernel again and again: RecursiveSkeletons' animation bake (840 joints) spent a
// third of its time in page faults.
#pragma once

namespace crowd {

// Blocks under 32 MiB come from the heap (glibc's own ceiling for the threshold it otherwise
// raises as it goes), and a heap gives memory back only past 256 MiB free at its top. A no-op
// on other C libraries. Call once, first thing in main (after useHugePages).
void keepFreedMemory();

// Where GLIBC_TUNABLES does not set glibc.malloc.hugetlb, sets it to 1 (the allocator asks the
// kernel for transparent huge pages on what it maps and on its heap) and runs the program again
// with the same arguments: glibc reads its tunables only as a process starts. Where the kernel
// gives huge pages only when asked (its default `madvise` mode), a page fault is taken per 2 MiB
// instead of per 4 KiB: lod_bench on its two 1M-triangle grids took 260,816 faults, and the
// bumpy grid's LOD 3.85 s; now about 3,000 faults and 2.3 s. Setting the tunable to 0 turns it
// off. Returns only where it does not run the program again (set already, no glibc, or the
// exec failed).
void useHugePages(char *const argv[]);

} // namespace crowd
