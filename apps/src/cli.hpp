#pragma once
namespace strata::app {
/// Runs the `strata` command line; returns the exit status (0 ok, 1 run failed, 2 bad usage/scene).
int main(int argc, char** argv);
}  // namespace strata::app
