#include "strata/io/plot.hpp"

#include <cmath>

#include "atomic_file.hpp"
#include "strata/config.hpp"
#include "strata/core/error.hpp"
#include "strata/core/log.hpp"
#include "strata/io/display.hpp"

#if STRATA_WITH_RENDER
#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>
#endif

namespace strata::io {

#if STRATA_WITH_RENDER
namespace {
// Tableau 10, the matplotlib default cycle: distinct and colour-blind tolerant.
constexpr unsigned char kPalette[][3] = {{31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
                                         {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {127, 127, 127},
                                         {188, 189, 34},  {23, 190, 207}};

void style_axis(vtkAxis* axis, const std::string& title, int font, bool log_scale) {
  axis->SetTitle(title);
  axis->GetTitleProperties()->SetFontSize(font);
  axis->GetTitleProperties()->SetColor(0.1, 0.1, 0.1);
  axis->GetTitleProperties()->BoldOff();
  axis->GetLabelProperties()->SetFontSize(static_cast<int>(font * 0.85));
  axis->GetLabelProperties()->SetColor(0.1, 0.1, 0.1);
  axis->GetGridPen()->SetColor(220, 220, 220);
  axis->SetLogScale(log_scale);
}
/// Ticks at 1, 2, 5 x 10^k (or 10^k alone over many decades) for a log axis over
/// [lo, hi] (data units, lo > 0): VTK's own log ticks are sparse within a decade.
void log_ticks(vtkAxis* axis, double lo, double hi) {
  if (!(lo > 0) || !(hi >= lo)) return;
  const int k0 = static_cast<int>(std::floor(std::log10(lo))),
            k1 = static_cast<int>(std::ceil(std::log10(hi)));
  static const std::vector<double> kTiers[] = {{1}, {1, 2, 5}, {1, 2, 3, 4, 5, 6, 7, 8, 9}};
  const int first_tier = k1 - k0 > 3 ? 0 : 1;
  for (int tier = first_tier; tier < 3; ++tier) {
    vtkNew<vtkDoubleArray> pos;
    vtkNew<vtkStringArray> labels;
    for (int k = k0; k <= k1; ++k)
      for (double m : kTiers[tier]) {
        const double v = m * std::pow(10.0, k);
        if (v < lo * 0.999 || v > hi * 1.001) continue;
        pos->InsertNextValue(std::log10(v));
        labels->InsertNextValue(fmt::format("{:g}", v));
      }
    if (pos->GetNumberOfTuples() >= 3 || (tier == 2 && pos->GetNumberOfTuples() >= 2)) {
      axis->SetCustomTickPositions(pos, labels);
      return;
    }
  }
}
}  // namespace

void plot_xy(const PlotRequest& rq) {
  STRATA_CHECK(!rq.png.empty(), Input, "plot_xy: no output file given");
  STRATA_CHECK(!rq.series.empty(), Input, "plot_xy({}): no series", rq.png.string());
  STRATA_CHECK(rq.width >= 64 && rq.height >= 64 && rq.width <= 8192 && rq.height <= 8192, Input,
               "plot_xy: size {}x{} outside 64..8192 pixels", rq.width, rq.height);
  ensure_display();
  const int font = std::max(10, rq.height / 36);

  vtkNew<vtkContextView> view;
  view->GetRenderer()->SetBackground(1, 1, 1);
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(rq.width, rq.height);
  view->GetRenderWindow()->SetMultiSamples(0);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetTitle(rq.title);
  chart->GetTitleProperties()->SetFontSize(static_cast<int>(font * 1.2));
  chart->GetTitleProperties()->SetColor(0.1, 0.1, 0.1);
  chart->GetTitleProperties()->BoldOn();
  style_axis(chart->GetAxis(vtkAxis::BOTTOM), rq.x_label, font, rq.log_x);
  style_axis(chart->GetAxis(vtkAxis::LEFT), rq.y_label, font, rq.log_y);

  std::vector<vtkSmartPointer<vtkTable>> tables;                // kept alive until the render
  double xlo = 1e300, xhi = -1e300, ylo = 1e300, yhi = -1e300;  // shown data range
  bool bars = false;                                            // any error bar drawn
  for (std::size_t k = 0; k < rq.series.size(); ++k) {
    const PlotSeries& ps = rq.series[k];
    STRATA_CHECK(ps.x.size() == ps.y.size(), Input,
                 "plot_xy({}): series '{}' has {} x values and {} y values", rq.png.string(), ps.name,
                 ps.x.size(), ps.y.size());
    vtkNew<vtkDoubleArray> xs, ys;
    xs->SetName("x");
    ys->SetName(ps.name.empty() ? fmt::format("series {}", k + 1).c_str() : ps.name.c_str());
    std::size_t dropped = 0;
    for (std::size_t i = 0; i < ps.x.size(); ++i) {
      const double x = ps.x[i], y = ps.y[i];
      if (!std::isfinite(x) || !std::isfinite(y) || (rq.log_x && x <= 0) || (rq.log_y && y <= 0)) {
        ++dropped;
        continue;
      }
      xs->InsertNextValue(x);
      ys->InsertNextValue(y);
      xlo = std::min(xlo, x), xhi = std::max(xhi, x), ylo = std::min(ylo, y), yhi = std::max(yhi, y);
    }
    if (dropped)
      log::warn("plot {}: {} points of '{}' left out (not finite, or <= 0 on a log axis)", rq.png.string(),
                dropped, ps.name);
    auto table = vtkSmartPointer<vtkTable>::New();
    table->AddColumn(xs);
    table->AddColumn(ys);
    tables.push_back(table);
    if (xs->GetNumberOfTuples() == 0) continue;
    const auto* c = kPalette[k % std::size(kPalette)];
    const float width = std::max(2.0f, rq.height / 400.0f);
    STRATA_CHECK(ps.y_err.empty() || ps.y_err.size() == ps.y.size(), Input,
                 "plot_xy({}): series '{}' has {} error values for {} points", rq.png.string(), ps.name,
                 ps.y_err.size(), ps.y.size());
    for (std::size_t i = 0; i < ps.y_err.size(); ++i) {
      const double x = ps.x[i], lo = ps.y[i] - ps.y_err[i], hi = ps.y[i] + ps.y_err[i];
      if (!(ps.y_err[i] > 0) || !std::isfinite(x) || !std::isfinite(lo) || !std::isfinite(hi) ||
          (rq.log_x && x <= 0) || (rq.log_y && lo <= 0))
        continue;
      vtkNew<vtkDoubleArray> bx, by;
      bx->SetName("x");
      by->SetName("bar");
      for (const double y : {lo, hi}) bx->InsertNextValue(x), by->InsertNextValue(y);
      auto bar = vtkSmartPointer<vtkTable>::New();
      bar->AddColumn(bx);
      bar->AddColumn(by);
      tables.push_back(bar);
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(bar, 0, 1);
      line->SetColor(c[0], c[1], c[2], 255);
      line->SetWidth(0.6f * width);
      line->LegendVisibilityOff();
      ylo = std::min(ylo, lo), yhi = std::max(yhi, hi);
      bars = true;
    }
    if (ps.line) {
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(table, 0, 1);
      line->SetColor(c[0], c[1], c[2], 255);
      line->SetWidth(width);
      if (ps.markers) {
        if (auto* pp = vtkPlotPoints::SafeDownCast(line)) {
          pp->SetMarkerStyle(vtkPlotPoints::CIRCLE);
          pp->SetMarkerSize(3 * width);
        }
      }
    } else {
      vtkPlot* pts = chart->AddPlot(vtkChart::POINTS);
      pts->SetInputData(table, 0, 1);
      pts->SetColor(c[0], c[1], c[2], 255);
      if (auto* pp = vtkPlotPoints::SafeDownCast(pts)) {  // points alone: large enough to find
        pp->SetMarkerStyle(vtkPlotPoints::CIRCLE);
        pp->SetMarkerSize(6 * width);
      }
    }
  }
  if (bars && !rq.log_x && xhi > xlo) {  // a margin, so the end points' error bars clear the frame
    const double pad = 0.04 * (xhi - xlo);
    vtkAxis* ax = chart->GetAxis(vtkAxis::BOTTOM);
    ax->SetBehavior(vtkAxis::FIXED);
    ax->SetRange(xlo - pad, xhi + pad);
  }
  if (rq.log_x) log_ticks(chart->GetAxis(vtkAxis::BOTTOM), xlo, xhi);
  if (rq.log_y) log_ticks(chart->GetAxis(vtkAxis::LEFT), ylo, yhi);
  if (rq.series.size() > 1) {
    chart->SetShowLegend(true);
    chart->GetLegend()->GetLabelProperties()->SetFontSize(static_cast<int>(font * 0.9));
    chart->GetLegend()->GetLabelProperties()->SetColor(0.1, 0.1, 0.1);
    chart->GetLegend()->GetBrush()->SetColor(255, 255, 255, 230);
  }

  view->GetRenderWindow()->Render();
  detail::make_parent(rq.png);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(view->GetRenderWindow());
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  const auto tmp = std::filesystem::path(rq.png.string() + ".tmp");
  vtkNew<vtkPNGWriter> w;
  w->SetFileName(tmp.c_str());
  w->SetInputConnection(grab->GetOutputPort());
  w->Write();
  STRATA_CHECK(w->GetErrorCode() == 0 && std::filesystem::exists(tmp), IO, "could not write PNG {}",
               rq.png.string());
  detail::commit(tmp, rq.png);
}

#else

void plot_xy(const PlotRequest&) { fail_missing_feature("STRATA_WITH_RENDER", "plots"); }

#endif

}  // namespace strata::io
