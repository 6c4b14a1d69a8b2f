// glibc's allocator, set for a baker: freed memory is kept for the next allocation instead of
// going back to the kernel. By default glibc maps every block over 128 KiB on its own and trims
// its heap whenever 128 KiB at the top are free, so a bake that allocates and frees a frame's
// worth of buffers per time it samples took the same pages from the kernel again and again:
// RecursiveSkeletons' animation bake (840 joints) spent a third of its time in page faults.
#pragma once

namespace crowd {

// Blocks under 32 MiB come from the heap (glibc's own ceiling for the threshold it otherwise
// raises as it goes), and a heap gives memory back only past 256 MiB free at its top. A no-op
// on other C libraries. Call once, first thing in main.
void keepFreedMemory();

} // namespace crowd
