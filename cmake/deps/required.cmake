# Required everywhere: fmt/spdlog for messages, toml++ for scene files, CLI11 for the command
# line, Eigen for small dense algebra and sparse matrices, nlohmann_json for JSON reports,
# Boost.Align (header only) for arrays that start a cache line.
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(CLI11 REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3 REQUIRED)
find_package(Boost 1.74 REQUIRED)
