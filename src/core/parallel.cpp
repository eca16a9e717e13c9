#include "core/parallel.hpp"

#include <dlfcn.h>

namespace crackle {

void pin_blas_threads() {
    // Looked up, not linked: Debian's libblas.so.3 may be OpenBLAS or the reference BLAS.
    using SetThreads = void (*)(int);
    if (void* f = ::dlsym(RTLD_DEFAULT, "openblas_set_num_threads")) reinterpret_cast<SetThreads>(f)(1);
}

} // namespace crackle
