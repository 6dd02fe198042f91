#include "coral_introspection/eval/training_report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "coral_introspection/coral/metrics.hpp"

namespace coral_introspection {
namespace eval {

bool writeTextFile(const std::string& path, const std::string& text, std::string* error) {
  std::ofstream f(path);
  f << text;
  f.close();
  if (!f) {
    if (error) *error = "cannot write " + path;
    return false;
  }
  return true;
}

bool writeSamplesCsv(const std::string& path, const SampleSet& set, std::string* error) {
  std::ostringstream s;
  // The dataset column only when a sample names its data set (sets of several data sets).
  const bool with_dataset = std::any_of(set.samples.begin(), set.samples.end(),
                                        [](const Sample& x) { return !x.dataset.empty(); });
  s << "pair,stamp_a,stamp_b,offset,dx,dy,dyaw,group,label" << (with_dataset ? ",dataset" : "");
  for (const MethodSpec& m : set.methods)
    for (const std::string& f : m.feature_names) s << ',' << m.name << '/' << f;
  s << '\n' << std::setprecision(10);
  for (const Sample& x : set.samples) {
    s << x.pair << ',' << std::fixed << std::setprecision(6) << x.stamp_a << ',' << x.stamp_b
      << std::defaultfloat << std::setprecision(10) << ',' << x.offset << ',' << x.dx << ',' << x.dy
      << ',' << x.dyaw << ',' << x.group << ',' << x.label;
    if (with_dataset) s << ',' << x.dataset;
    s << std::setprecision(17);  // features round-trip exactly: a refit from the file is equal
    for (const auto& f : x.features)
      for (double v : f) s << ',' << v;  // NaN = method gave no value
    s << '\n';
  }
  return writeTextFile(path, s.str(), error);
}

bool writeClassifierYaml(const std::string& path, const coral::ClassifierConfig& c,
                         const std::vector<std::string>& comments, std::string* error) {
  return writeTextFile(path, coral::classifierYaml(c, comments), error);
}

namespace {
std::string fmt(double v) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream s;
  s << std::fixed << std::setprecision(2) << v;
  return s.str();
}
}  // namespace

std::string markdownTables(const std::vector<EvaluationRow>& rows,
                           const std::vector<std::string>& groups) {
  std::ostringstream s;
  std::vector<std::string> methods;
  for (const EvaluationRow& r : rows)
    if (std::find(methods.begin(), methods.end(), r.method) == methods.end())
      methods.push_back(r.method);
  s << "| Method |";
  for (const std::string& g : groups) s << ' ' << g << " |";
  s << "\n|---|";
  for (std::size_t i = 0; i < groups.size(); ++i) s << "---|";
  s << '\n';
  for (const std::string& m : methods) {
    s << "| " << m << " |";
    for (const std::string& g : groups)
      for (const EvaluationRow& r : rows)
        if (r.method == m && r.group == g) s << ' ' << fmt(r.accuracy) << '/' << fmt(r.auc) << " |";
    s << '\n';
  }
  s << "\nCells: held-out balanced accuracy / AUC.\n\n"
    << "| Method | Error | Accuracy (balanced) | Accuracy (plain) | AUC | Pairs | Aligned | "
       "Misaligned | No value | Folds |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const EvaluationRow& r : rows)
    s << "| " << r.method << " | " << r.group << " | " << fmt(r.accuracy) << " | "
      << fmt(r.plain_accuracy) << " | " << fmt(r.auc) << " | " << r.pairs << " | " << r.aligned
      << " | " << r.misaligned << " | " << r.skipped << " | " << r.folds << " |\n";
  return s.str();
}

bool writeRocPng(const std::string& path, const std::vector<EvaluationRow>& rows,
                 const std::vector<std::string>& groups, std::string* error) {
  const int P = 360, M = 50, W = M + P + 20, H = M + P + 60;  // panel geometry [px]
  const int ng = std::max<int>(1, static_cast<int>(groups.size()));
  cv::Mat img(H, W * ng, CV_8UC3, cv::Scalar(255, 255, 255));
  static const cv::Scalar colours[] = {{200, 0, 0},   {0, 0, 220},   {0, 150, 0},
                                       {0, 140, 255}, {160, 0, 160}, {128, 128, 0},
                                       {60, 60, 60},  {0, 200, 200}, {255, 100, 100}};
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (int gi = 0; gi < ng; ++gi) {
    const int x0 = gi * W + M, y0 = 30;  // top-left of the plot area
    auto px = [&](double fpr, double tpr) {
      return cv::Point(x0 + static_cast<int>(std::lround(fpr * P)),
                       y0 + P - static_cast<int>(std::lround(tpr * P)));
    };
    cv::rectangle(img, px(0, 1), px(1, 0), cv::Scalar(0, 0, 0), 1);
    cv::line(img, px(0, 0), px(1, 1), cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
    if (gi < static_cast<int>(groups.size()))
      cv::putText(img, "ROC, error " + groups[gi], cv::Point(x0, 20), font, 0.5, {0, 0, 0}, 1,
                  cv::LINE_AA);
    cv::putText(img, "false-positive rate", cv::Point(x0 + P / 2 - 70, y0 + P + 35), font, 0.45,
                {0, 0, 0}, 1, cv::LINE_AA);
    cv::putText(img, "TPR", cv::Point(x0 - 45, y0 + P / 2 - 25), font, 0.45, {0, 0, 0}, 1,
                cv::LINE_AA);
    for (double t : {0.0, 0.5, 1.0}) {
      std::ostringstream l;
      l << t;
      cv::putText(img, l.str(), px(t, 0) + cv::Point(-5, 15), font, 0.4, {0, 0, 0}, 1, cv::LINE_AA);
      cv::putText(img, l.str(), px(0, t) + cv::Point(-25, 5), font, 0.4, {0, 0, 0}, 1, cv::LINE_AA);
    }
    int k = 0, legend_y = y0 + P - 10;
    for (const EvaluationRow& r : rows) {
      if (gi >= static_cast<int>(groups.size()) || r.group != groups[gi]) continue;
      const cv::Scalar c = colours[k++ % 9];
      const std::vector<coral::RocPoint> roc = coral::rocCurve(r.scores, r.labels);
      for (std::size_t i = 1; i < roc.size(); ++i)
        cv::line(img, px(roc[i - 1].fpr, roc[i - 1].tpr), px(roc[i].fpr, roc[i].tpr), c, 2,
                 cv::LINE_AA);
      cv::putText(img, r.method + " AUC " + fmt(r.auc), cv::Point(x0 + P - 170, legend_y), font,
                  0.4, c, 1, cv::LINE_AA);
      legend_y -= 15;
    }
  }
  bool ok = false;
  try {
    ok = cv::imwrite(path, img);
  } catch (const cv::Exception& e) {
    ok = false;
  }
  if (!ok && error) *error = "cv::imwrite failed for " + path;
  return ok;
}

}  // namespace eval
}  // namespace coral_introspection
