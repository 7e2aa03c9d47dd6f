#include "cli.hpp"
namespace strata::app {
int main(int, char**) { return 0; }
}  // namespace strata::app
