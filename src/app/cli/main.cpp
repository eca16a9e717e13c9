#include "app/cli/cli.hpp"
#include "core/atomic_file.hpp"
#include "core/parallel.hpp"

#include <iostream>
#include <malloc.h>

int main(int argc, char** argv) {
    // Big buffers (maps, matrices) come from the heap and go back to it, not to the kernel: by
    // default glibc maps large blocks (all over 32 MB) with mmap and unmaps them when freed, and
    // on these KVM guests a page fault is dear — the bake's relief pass spent half its time
    // faulting in pages it had just freed (2048² mud: relief 6.2 s → 3.4 s, maps byte-identical,
    // peak memory 591 → 719 MB; docs/benchmarks.md, "Speed-ups and what they kept").
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    // Ctrl-C, TERM and HUP remove the temporaries of files not yet in place (issue 16).
    crackle::install_interrupt_cleanup();
    crackle::pin_blas_threads(); // direct solves sum alike on every machine (issue 16)
    return crackle::app::run(argc, argv, std::cout, std::cerr);
}
