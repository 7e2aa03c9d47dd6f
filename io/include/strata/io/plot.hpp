#pragma once
/// Line plots to PNG with VTK charts (vtkChartXY in an off-screen vtkContextView):
/// stress-strain curves, energy histories, error-versus-run-time reports.
/// Without STRATA_WITH_RENDER plot_xy throws strata::Error (Unsupported).
#include <filesystem>
#include <string>
#include <vector>

namespace strata::io {

/// One curve: y against x (same length).
struct PlotSeries {
  std::string name;  ///< legend entry
  std::vector<double> x;
  std::vector<double> y;
  bool markers = false;  ///< draw points as well as (or, with `line` false, instead of) the line
  bool line = true;
  /// Empty, or one value per point: a vertical bar from y − e to y + e (e.g. a standard
  /// deviation), in the series' colour.
  std::vector<double> y_err{};
};

struct PlotRequest {
  std::string title;
  std::string x_label;  ///< with unit, e.g. "axial strain [-]"
  std::string y_label;  ///< e.g. "axial stress [MPa]"
  std::vector<PlotSeries> series;
  bool log_x = false;  ///< points with x <= 0 are left out (with a warning)
  bool log_y = false;
  std::filesystem::path png;
  int width = 1200;
  int height = 800;
};

/// Writes the plot to `request.png` (parent folders created); a legend is shown when there
/// is more than one series. Starts Xvfb if needed.
void plot_xy(const PlotRequest& request);

}  // namespace strata::io
