// doctest main, in its own translation unit (it is slow to compile and rarely changes).
#define DOCTEST_CONFIG_IMPLEMENT
#include "core/parallel.hpp"

#include <doctest/doctest.h>

#include <cstdlib>

int main(int argc, char** argv) {
    // Tests are hermetic: no pattern cache in the user's home folder, and no test served a
    // pattern another test simulated. The cache's own tests point CRACKLE_CACHE at a scratch folder.
    setenv("CRACKLE_CACHE", "off", 1);
    crackle::pin_blas_threads(); // as the CLI does: the same sums on every machine

    return doctest::Context(argc, argv).run();
}
