// The `strata` command: a thin main() around strata_app (apps/src/cli.cpp).
#include "cli.hpp"

int main(int argc, char** argv) { return strata::app::main(argc, argv); }
