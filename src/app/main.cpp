#include "app/cli.hpp"

#include <iostream>

int main(int argc, char** argv) {
    return crackle::app::run(argc, argv, std::cout, std::cerr);
}
