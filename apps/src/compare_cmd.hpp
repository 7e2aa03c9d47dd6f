#pragma once
// `strata compare`: one scene at several η against a reference scene, as a table and plots of
// gauge error against run time (the work is in strata::cases::compare_runs).
#include <strata/cases/compare.hpp>

namespace strata::app {

/// Runs the comparison, prints the table and the files written; returns the exit status
/// (130/143 when a run was stopped by SIGINT/SIGTERM).
int compare_cmd(const cases::CompareOptions& opt, int threads);

}  // namespace strata::app
