#include "report/study_report.h"

#include <algorithm>
#include <string>

#include "engine/atomic_file.h"
#include "plot/plot.h"
#include "study/report.h"

namespace pwsim::report {

void RemoveStudyReport(const std::filesystem::path& out) {
  const plot::FigureFiles figure = plot::FigureFilesFor(out / "boxplot");
  for (const std::filesystem::path& old :
       {out / "study.json", out / "study.md", figure.png, figure.svg, figure.csv, figure.gp})
    std::filesystem::remove(old);
}

void WriteStudyReport(const std::filesystem::path& out, const std::filesystem::path& ratings_file,
                      const study::Ratings& ratings, const study::StudyAnalysis& analysis) {
  const std::string json = study::StudyJson(analysis);
  const std::string md = study::StudyMarkdown(analysis, ratings_file.string(), "boxplot.png");

  // Fig. 8b: median, quartiles and extremes per condition, every rating shown.
  plot::Figure fig;
  fig.title = "How the participants rated each ride (" + std::to_string(ratings.participants.size()) +
              " participants; box: quartiles and median, whiskers: extremes, dots: each rating)";
  fig.width_px = 900;
  fig.panel_height_px = 480;
  plot::Panel panel;
  panel.y_label = "rating (1 = accurate ... 6 = no motion perceived)";
  double lo = 1.0, hi = 6.0;
  for (const study::ConditionSummary& c : analysis.conditions) {
    plot::BoxGroup box;
    // seed 000's two conditions in words (pwsim session --sources: T_r=measured, T_m=model by default)
    box.label = c.name == "T_r"   ? "T_r: tracked motion of the real chair"
                : c.name == "T_m" ? "T_m: motion of the chair model"
                                  : c.name;
    box.values = c.values;
    panel.boxes.push_back(box);
    lo = std::min(lo, c.stats.min);
    hi = std::max(hi, c.stats.max);
  }
  panel.y_min = lo - 0.5;
  panel.y_max = hi + 0.5;
  panel.box_whiskers_to_extremes = true;
  panel.box_show_points = true;
  panel.y_tic_step = 1.0;  // the scale's steps
  fig.panels.push_back(panel);
  plot::WriteFigure(out / "boxplot", fig);
  WriteFileAtomically(out / "study.md", md);
  WriteFileAtomically(out / "study.json", json);
}

}  // namespace pwsim::report
