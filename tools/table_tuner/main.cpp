// table_tuner: coordinate descent over every entry of the zone tables b, c0, c1 for
// mean |error vs the 25-point lattice| + lambda * rays on a population of single-pixel
// edge configurations (aa/table_tuning.h), one table set per lambda. Prints the Pareto
// points, writes them as CSV, and optionally writes the chosen sets ("tuned": best error
// within the paper's ray budget; "tuned-hq": fewest rays within 5 % of tracing every
// zone) as the C++ include host/aa/tuned_tables.inc.
//
//   table_tuner [--csv pareto.csv] [--write-inc host/aa/tuned_tables.inc] [--eps 0.1]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "aa/table_tuning.h"

using namespace zz;

namespace {

struct Point {
  double lambda;
  TableSet tables;
  TableScore train, held_out;
};

std::string row(const uint8_t* t) {
  std::string s = "{";
  for (int i = 0; i < 16; ++i) s += std::to_string(int(t[i])) + (i < 15 ? ", " : "}");
  return s;
}

void write_set(std::ofstream& f, const char* var, const char* name, const Point& p, const TableScore& paper_held_out,
               double eps) {
  f << "// " << name << ": lambda = " << p.lambda << ", eps = " << eps
    << ". Held-out population: mean |error vs 25-point lattice|\n// " << p.held_out.error << " at "
    << p.held_out.rays << " rays/px (paper: " << paper_held_out.error << " at " << paper_held_out.rays
    << " rays/px).\n"
    << "constexpr TableSet " << var << " = {\n    \"" << name << "\",\n    " << row(p.tables.b) << ",\n    "
    << row(p.tables.c0) << ",\n    " << row(p.tables.c1) << ",\n};\n";
}

}  // namespace

int main(int argc, char** argv) {
  const char* csv = "pareto.csv";
  const char* inc = nullptr;
  AdaptiveSettings settings;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--csv")) csv = argv[i + 1];
    else if (!std::strcmp(argv[i], "--write-inc")) inc = argv[i + 1];
    else if (!std::strcmp(argv[i], "--eps")) settings.eps = float(std::atof(argv[i + 1]));
    else {
      std::fprintf(stderr, "usage: table_tuner [--csv FILE] [--write-inc FILE] [--eps E]\n");
      return 2;
    }
  }
  const Population pop = make_population();
  const std::vector<PatternRecord> train = evaluate_population(pop.train, settings);
  const std::vector<PatternRecord> held = evaluate_population(pop.held_out, settings);
  const TableSet& paper = *find_table_set("paper");
  const TableSet& all = *find_table_set("all");
  const TableScore paper_train = score_tables(paper, train), paper_held = score_tables(paper, held);
  const TableScore all_held = score_tables(all, held);
  std::printf("population: %zu train, %zu held-out (eps %g)\n", train.size(), held.size(), double(settings.eps));
  std::printf("%-10s %10s %10s %12s %12s\n", "set", "lambda", "rays/px", "err(train)", "err(held)");
  std::printf("%-10s %10s %10.3f %12.6f %12.6f\n", "paper", "-", paper_held.rays, paper_train.error, paper_held.error);
  std::printf("%-10s %10s %10.3f %12.6f %12.6f\n", "all", "-", all_held.rays, score_tables(all, train).error,
              all_held.error);

  const double lambdas[] = {0.0, 5e-5, 1e-4, 2e-4, 3e-4, 5e-4, 7e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 5e-3, 1e-2, 2e-2};
  std::vector<Point> points;
  for (double lambda : lambdas) {
    // Two starts (the paper's tables and "all"); keep the better train objective.
    TableSet a = tune_tables(paper, train, lambda), b = tune_tables(all, train, lambda);
    TableSet best = score_tables(a, train).objective(lambda) <= score_tables(b, train).objective(lambda) ? a : b;
    Point p{lambda, best, score_tables(best, train), score_tables(best, held)};
    points.push_back(p);
    std::printf("%-10s %10.5f %10.3f %12.6f %12.6f\n", "tuned", lambda, p.held_out.rays, p.train.error,
                p.held_out.error);
  }

  std::ofstream f(csv);
  f << "set,lambda,rays_per_px_held_out,error_held_out,rays_per_px_train,error_train,b,c0,c1\n";
  auto emit = [&](const char* name, double lambda, const TableSet& t, const TableScore& tr, const TableScore& ho) {
    f << name << "," << lambda << "," << ho.rays << "," << ho.error << "," << tr.rays << "," << tr.error << ",\""
      << row(t.b) << "\",\"" << row(t.c0) << "\",\"" << row(t.c1) << "\"\n";
  };
  emit("paper", -1, paper, paper_train, paper_held);
  emit("all", -1, all, score_tables(all, train), all_held);
  for (const Point& p : points) emit("tuned", p.lambda, p.tables, p.train, p.held_out);

  // The shipped set: the lowest train error among sets that use no more rays than the
  // paper on the train population (chosen on train, reported on held-out).
  const Point* chosen = nullptr;
  for (const Point& p : points)
    if (p.train.rays <= paper_train.rays && (!chosen || p.train.error < chosen->train.error)) chosen = &p;
  if (!chosen) {
    std::fprintf(stderr, "no tuned set within the paper's ray budget\n");
    return 1;
  }
  std::printf("chosen: lambda %g, held-out %.6f at %.3f rays/px (paper %.6f at %.3f)\n", chosen->lambda,
              chosen->held_out.error, chosen->held_out.rays, paper_held.error, paper_held.rays);
  // A second, quality-first set: the lambda whose error is within 5 % of tracing every
  // zone (the population's floor) with the fewest rays.
  const TableScore all_train = score_tables(all, train);
  const Point* hq = nullptr;
  for (const Point& p : points)
    if (p.train.error <= 1.05 * all_train.error && (!hq || p.train.rays < hq->train.rays)) hq = &p;
  std::printf("tuned-hq: lambda %g, held-out %.6f at %.3f rays/px\n", hq->lambda, hq->held_out.error,
              hq->held_out.rays);
  if (inc) {
    std::ofstream out(inc);
    out << "// Written by tools/table_tuner (do not edit by hand). Zone bit z = zone z.\n";
    write_set(out, "kTuned", "tuned", *chosen, paper_held, settings.eps);
    write_set(out, "kTunedHq", "tuned-hq", *hq, paper_held, settings.eps);
  }
  return 0;
}
