// doc/verdict_every_error.md's table of the gate terms each preset ships is rendered here from
// the presets themselves (the loader the nodelet and coral_check use): a value changed in
// config/*.yaml without the table following makes this fail, and the message prints the table
// to paste.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/preset.hpp"
#include "support/source_dir.hpp"

namespace coral = coral_introspection::coral;
namespace ros_adapters = coral_introspection::ros_adapters;

namespace {

coral::VerdictConfig presetVerdict(const std::string& name) {
  ros_adapters::NodeConfig c;
  coral_test::loadPreset(name, &c);
  return c.online.verdict;
}

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// One column of the table: a gate (stream or loop) with the relative check's margin it uses.
struct Column {
  coral::GateConfig gate;
  double margin;
  bool loop;
};

Column stream(const coral::VerdictConfig& v) { return {v.gate, v.relative.margin, false}; }
Column loop(const coral::VerdictConfig& v) {
  const double m =
      v.loop_closure.relative_margin >= 0 ? v.loop_closure.relative_margin : v.relative.margin;
  return {v.loop_closure, m, true};
}

// Each row: its label and the cell of one column ("" = the term is off).
struct Row {
  const char* label;
  std::string (*cell)(const Column&);
};

const std::vector<Row>& rows() {
  static const std::vector<Row> r = {
      {"classifier p >= (`min_probability`)",
       [](const Column& c) {
         return c.gate.min_probability > 0 ? num(c.gate.min_probability) : "";
       }},
      {"overlap >= (`min_overlap`)",
       [](const Column& c) { return c.gate.min_overlap > 0 ? num(c.gate.min_overlap) : ""; }},
      {"free-space conflict <= (`max_free_space`)",
       [](const Column& c) { return c.gate.max_free_space < 1 ? num(c.gate.max_free_space) : ""; }},
      {"constraint >= (`min_constraint`, 1 deg beams)",
       [](const Column& c) { return c.gate.min_constraint > 0 ? num(c.gate.min_constraint) : ""; }},
      {"Q <= (`max_quality`)",
       [](const Column& c) {
         return std::isfinite(c.gate.max_quality) ? num(c.gate.max_quality) : "";
       }},
      {"flat axes <= (`max_flat_axes`)",
       [](const Column& c) {
         return c.gate.max_flat_axes >= 0 ? std::to_string(c.gate.max_flat_axes) : "";
       }},
      {"relative margin", [](const Column& c) { return num(c.margin); }},
      {"coarse probe (`coarse_max_multiple`)",
       [](const Column& c) {
         std::string s = c.gate.coarse_max_multiple > 0 ? num(c.gate.coarse_max_multiple) : "";
         if (c.gate.coarse_registration) {
           s += s.empty() ? "registration" : ", registration";
           if (c.gate.coarse_min_registered_offset != 1.0)  // the default: not named
             s += " from " + num(c.gate.coarse_min_registered_offset);
         }
         if (c.gate.coarse_below_probability < 1)
           s += (s.empty() ? "p < " : ", p < ") + num(c.gate.coarse_below_probability);
         return s;
       }},
      {"refinement / restarts / registered once",
       [](const Column& c) -> std::string {
         const coral::GateConfig& g = c.gate;
         if (!c.loop || (g.max_refinement <= 0 && !g.restarts && g.max_registered_offset <= 0))
           return "";
         return (g.max_refinement > 0 ? num(g.max_refinement) : "off") + " / " +
                (g.restarts ? "on" : "off") + " / " +
                (g.max_registered_offset > 0 ? num(g.max_registered_offset) : "off");
       }},
  };
  return r;
}

// The table's lines in the doc, from its header line (starting "| term |") to the last row.
std::vector<std::string> docTable(const std::string& file) {
  std::ifstream in(coral_test::sourceDir() + "/" + file);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) {
    if (out.empty() && l.rfind("| term |", 0) != 0) continue;
    if (l.rfind("|", 0) != 0) break;
    out.push_back(l);
  }
  return out;
}

TEST(DocTables, GateTermsPerPresetMatchThePresets) {
  const coral::VerdictConfig l2 = presetVerdict("lidar_2d"), l3 = presetVerdict("lidar_3d"),
                             rad = presetVerdict("radar_oxford");
  // radar_oxford's one column holds both of its gates: they must be the same.
  for (const Row& r : rows())
    EXPECT_EQ(r.cell(stream(rad)), r.cell(loop(rad))) << "radar_oxford's gates differ: " << r.label;
  const std::vector<Column> cols = {stream(l2), loop(l2), stream(l3), loop(l3), stream(rad)};
  std::vector<std::string> want = {
      "| term | lidar_2d stream | lidar_2d loop | lidar_3d stream | lidar_3d loop | radar_oxford "
      "stream and loop |",
      "|---|---|---|---|---|---|"};
  for (const Row& r : rows()) {
    std::string line = std::string("| ") + r.label + " |";
    for (const Column& c : cols) {
      const std::string v = r.cell(c);
      line += v.empty() ? " |" : " " + v + " |";
    }
    want.push_back(line);
  }
  std::string table;
  for (const std::string& l : want) table += l + "\n";
  EXPECT_EQ(docTable("doc/verdict_every_error.md"), want)
      << "doc/verdict_every_error.md (Design) should hold the presets' table:\n"
      << table;
  // The 2D constraint bounds are stated for 1 deg beams (the row's label).
  for (const coral::GateConfig* g : {&l2.gate, &l2.loop_closure}) {
    if (g->min_constraint > 0) {
      EXPECT_EQ(g->constraint_beam_step_deg, 1.0);
    }
  }
}

}  // namespace
