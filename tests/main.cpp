// doctest main, in its own translation unit (it is slow to compile and rarely changes).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
