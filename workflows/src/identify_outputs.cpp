// The files of `isospring identify` besides its reports: marker point sets, the residual plot and
// data, the rms bars and model.json (see identify_command.hpp).
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/plot.hpp"
#include "isospring/io/svg_scatter.hpp"
#include "isospring/io/vtk_markers.hpp"
#include "isospring/workflows/identify_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

// Residual magnitude at every marker before and after: residuals.csv and residuals.svg (markers
// at their x and y positions; a 3D case shows its markers projected on x-y).
void write_residual_plot(const std::filesystem::path& out_dir,
                         const std::vector<fitting::Marker>& markers,
                         const fitting::IdentifyResult& r) {
  const std::filesystem::path data = out_dir / "residuals.csv";
  write_file_atomically(data, [&](std::ostream& out) {
    out << "load_case,x,y,z,residual_before,residual_after\n";
    for (size_t m = 0; m < markers.size(); ++m)
      out << markers[m].load_case << "," << format_exact(markers[m].position.x()) << ","
          << format_exact(markers[m].position.y()) << "," << format_exact(markers[m].position.z())
          << "," << format_exact((markers[m].displacement - r.model_before[m]).norm()) << ","
          << format_exact((markers[m].displacement - r.model_after[m]).norm()) << "\n";
  });
  // Small multiples (io/svg_scatter.hpp): one row per load case (its own colour scale, so a
  // case with small residuals is not hidden by one with large ones), before and after side by
  // side; the colour is |residual|, the column of residuals.csv.
  std::vector<ScatterRow> rows;
  for (const auto& lc : r.load_cases) {
    ScatterRow row;
    row.name = lc.id;
    for (const char* stage : {"before", "after"}) {
      const bool before = std::string(stage) == "before";
      const auto& model = before ? r.model_before : r.model_after;
      const fitting::ErrorSummary& e = before ? lc.before : lc.after;
      ScatterPanel panel;
      panel.column = stage;
      panel.title = lc.id + (before ? ", nominal model" : ", with effects") + ": rms " +
                    format_number(e.rms, 2) + " m, max |r| " + format_number(e.max_norm, 2) + " m";
      for (size_t m = 0; m < markers.size(); ++m) {
        if (markers[m].load_case != lc.id) continue;
        panel.x.push_back(markers[m].position.x());
        panel.y.push_back(markers[m].position.y());
        panel.value.push_back((markers[m].displacement - model[m]).norm());
      }
      row.panels.push_back(std::move(panel));
    }
    rows.push_back(std::move(row));
  }
  ScatterGridOptions options;
  options.title = "Marker residuals per load case: before and after the identified effects";
  options.value_label = "|residual| [m]";
  write_scatter_grid_svg(out_dir / "residuals.svg", rows, options);
}

void write_markers(const std::filesystem::path& out_dir,
                   const std::vector<std::string>& load_case_ids,
                   const std::vector<fitting::Marker>& markers, const fitting::IdentifyResult& r) {
  // One point set per load case with measured/model/residual; "before" and "after" files.
  for (const char* stage : {"before", "after"}) {
    const auto& model = std::string(stage) == "before" ? r.model_before : r.model_after;
    // Markers of different load cases may sit at different positions: one file per load case.
    for (const auto& id : load_case_ids) {
      MarkerData one;
      MarkerCase mc;
      mc.load_case = id;
      for (size_t m = 0; m < markers.size(); ++m) {
        if (markers[m].load_case != id) continue;
        one.positions.push_back(markers[m].position);
        mc.measured.push_back(markers[m].displacement);
        mc.model.push_back(model[m]);
      }
      if (one.positions.empty()) continue;
      one.cases.push_back(mc);
      write_markers_vtp(out_dir / ("markers_" + id + "_" + stage + ".vtp"), one);
    }
  }
}

// The marker residual rms before and after as bars (gnuplot); false when gnuplot is missing.
bool write_rms_bars(const std::filesystem::path& out_dir, const fitting::IdentifyResult& r) {
  std::vector<std::string> labels{"all"};
  std::vector<double> before{r.before.rms}, after{r.after.rms};
  for (const auto& lc : r.load_cases) {
    labels.push_back(lc.id);
    before.push_back(lc.before.rms);
    after.push_back(lc.after.rms);
  }
  PlotOptions bars;
  bars.title = "Marker residual rms: nominal model (before) and with the effects (after)";
  bars.ylabel = "rms residual [m]";
  bars.log_y = true;  // the effects often remove orders of magnitude
  return plot_bars_before_after(out_dir / "errors_before_after.png", labels, before, after, bars);
}

}  // namespace

void write_identify_outputs(const std::filesystem::path& out_dir, const IdentifyCommandResult& r,
                            const Progress& progress) {
  std::filesystem::create_directories(out_dir);
  const bool figure = write_rms_bars(out_dir, r.identify);
  nlohmann::json report = identify_report_json(r);
  MarkdownReport md = identify_report_markdown(r, figure);
  if (r.recalibration) write_spring_model_json(out_dir / "model.json", identify_spring_model(r));
  write_markers(out_dir, r.load_case_ids, r.markers, r.identify);
  write_residual_plot(out_dir, r.markers, r.identify);
  add_warnings(report, md, progress);
  write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
}

}  // namespace isospring::workflows
