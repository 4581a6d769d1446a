// bench_traversal [benchmark flags] [scene files...]
// Traversal throughput (Mrays/s) of zz::Bvh vs Embree 3 on identical rays: coherent
// primary packets (2x2 pixels), shadow rays to a point light and random hemisphere
// secondary rays, as 4-ray packets and as single rays, on 1 thread and on all threads.
// Ends with a table of ours/Embree ratios (medians when --benchmark_repetitions > 1).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <thread>

#include "embree_tracer.h"
#include "ray_sets.h"

namespace zz::bench {
namespace {

constexpr int kWidth = 512, kHeight = 512;

struct Entry {
  Workload work;
  Bvh bvh;
  std::unique_ptr<EmbreeTracer> embree;
  std::vector<Ray> single[3];  // the active lanes of each ray set, as single rays
};

enum Kind { kPrimary, kShadow, kSecondary };
const char* kKindNames[] = {"primary", "shadow", "secondary"};
enum Impl { kOurs4, kOurs1, kEmbree4, kEmbree1 };
const char* kImplNames[] = {"ours4", "ours1", "embree4", "embree1"};

const RaySet& set_of(const Workload& w, Kind k) {
  return k == kPrimary ? w.primary : (k == kShadow ? w.shadow : w.secondary);
}

std::vector<Ray> to_single(const RaySet& s) {
  std::vector<Ray> out;
  for (size_t p = 0; p < s.packets.size(); ++p)
    for (int i = 0; i < 4; ++i)
      if (s.masks[p] >> i & 1) {
        const RayPacket4& r = s.packets[p];
        out.push_back(Ray{{r.ox[i], r.oy[i], r.oz[i]}, {r.dx[i], r.dy[i], r.dz[i]}, r.tmax[i]});
      }
  return out;
}

void run(benchmark::State& state, const Entry* e, Kind kind, Impl impl) {
  const RaySet& set = set_of(e->work, kind);
  const std::vector<Ray>& single = e->single[kind];
  bool packets = impl == kOurs4 || impl == kEmbree4;
  size_t n = packets ? set.packets.size() : single.size();
  // Each thread traces a contiguous share of the same ray set (static split).
  size_t begin = n * size_t(state.thread_index()) / size_t(state.threads());
  size_t end = n * size_t(state.thread_index() + 1) / size_t(state.threads());
  size_t rays = 0;
  for (size_t i = begin; i < end; ++i) rays += packets ? size_t(__builtin_popcount(unsigned(set.masks[i]))) : 1;
  bool closest = kind != kShadow;
  int64_t sink = 0;
  for (auto _ : state) {
    for (size_t i = begin; i < end; ++i) {
      if (packets) {
        const RayPacket4& r = set.packets[i];
        int m = set.masks[i];
        if (closest) {
          HitPacket4 h;
          if (impl == kOurs4) {
            mask4 active((m & 1) != 0, (m & 2) != 0, (m & 4) != 0, (m & 8) != 0);
            e->bvh.intersect4(r, active, h);
          } else {
            e->embree->intersect4(r, m, h);
          }
          sink += h.prim[0];
        } else if (impl == kOurs4) {
          mask4 active((m & 1) != 0, (m & 2) != 0, (m & 4) != 0, (m & 8) != 0);
          sink += e->bvh.occluded4(r, active).bits();
        } else {
          sink += e->embree->occluded4(r, m);
        }
      } else if (closest) {
        sink += impl == kOurs1 ? e->bvh.intersect1(single[i]).prim : e->embree->intersect1(single[i]).prim;
      } else {
        sink += impl == kOurs1 ? e->bvh.occluded1(single[i]) : e->embree->occluded1(single[i]);
      }
    }
    benchmark::DoNotOptimize(sink);
  }
  state.counters["Mrays/s"] =
      benchmark::Counter(double(rays) * double(state.iterations()) * 1e-6, benchmark::Counter::kIsRate);
}

// Closest-hit agreement with Embree on the primary rays: shows both trace the same
// rays and geometry (prims differ only on ties and edge-on hits).
void report_agreement(const Entry& e) {
  if (!e.embree) return;
  size_t same = 0, total = 0, hits = 0;
  for (size_t p = 0; p < e.work.primary.packets.size(); ++p) {
    HitPacket4 a, b;
    e.bvh.intersect4(e.work.primary.packets[p], mask4(true), a);
    e.embree->intersect4(e.work.primary.packets[p], 0xF, b);
    for (int i = 0; i < 4; ++i) same += a.prim[i] == b.prim[i], hits += a.prim[i] >= 0, ++total;
  }
  std::printf("  primary hits %.1f%%, same prim as Embree %.3f%%\n", 100.0 * double(hits) / double(total),
              100.0 * double(same) / double(total));
}

// Collects the Mrays/s of every run (median aggregates when repeated) for the ratio table.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      bool aggregate = r.run_type == Run::RT_Aggregate;
      if (aggregate && r.aggregate_name != "median") continue;
      if (!aggregate && r.repetitions > 1) continue;
      auto it = r.counters.find("Mrays/s");
      if (it == r.counters.end()) continue;
      rates[r.run_name.function_name][int(r.threads)] = it->second.value;
    }
  }
  std::map<std::string, std::map<int, double>> rates;  // "scene/kind/impl" -> threads -> Mrays/s
};

}  // namespace
}  // namespace zz::bench

int main(int argc, char** argv) {
  using namespace zz::bench;
  benchmark::Initialize(&argc, argv);
  std::vector<std::string> paths(argv + 1, argv + argc);
  if (paths.empty()) {
    std::string root = ZZ_SOURCE_DIR;
    paths = {root + "/scenes/room.json", root + "/scenes/glass.json", root + "/scenes/car.json"};
  }
  std::vector<Mesh> meshes;
  bool fallback = false;
  for (const std::string& p : paths) {
    std::string why;
    Mesh m = load_mesh(p, &why);
    if (m.positions.empty()) {
      std::printf("scene %s: %s\n", p.c_str(), why.empty() ? "no triangles" : why.c_str());
      fallback = true;
      continue;
    }
    meshes.push_back(std::move(m));
  }
  if (fallback || meshes.empty()) {
    std::printf("adding generated meshes\n");
    meshes.push_back(random_soup_mesh(150000));
    meshes.push_back(heightfield_mesh(274));  // 150k triangles
  }

  std::vector<std::unique_ptr<Entry>> entries;
  for (Mesh& m : meshes) {
    auto e = std::make_unique<Entry>();
    zz::BvhBuildStats st;
    e->bvh = zz::Bvh::build(m.positions, &st);
    e->work = make_workload(std::move(m), e->bvh, kWidth, kHeight);
    for (int k = 0; k < 3; ++k) e->single[k] = to_single(set_of(e->work, Kind(k)));
    std::printf("%s: %zu triangles; BVH %.3f s, %zu nodes, %zu leaves, depth %zu, SAH %.1f\n",
                e->work.mesh.name.c_str(), e->work.mesh.positions.size() / 3, st.build_seconds,
                st.node_count, st.leaf_count, st.max_depth, st.sah_cost);
    std::printf("  rays: primary %zu, shadow %zu, secondary %zu\n", e->work.primary.ray_count,
                e->work.shadow.ray_count, e->work.secondary.ray_count);
    if (EmbreeTracer::available()) {
      e->embree = std::make_unique<EmbreeTracer>(e->work.mesh.positions);
      std::printf("  Embree build %.3f s\n", e->embree->build_seconds());
      report_agreement(*e);
    }
    entries.push_back(std::move(e));
  }

  int all = int(std::max(1u, std::thread::hardware_concurrency()));
  for (auto& e : entries)
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 4; ++i) {
        if ((i == kEmbree4 || i == kEmbree1) && !e->embree) continue;
        std::string name = e->work.mesh.name + "/" + kKindNames[k] + "/" + kImplNames[i];
        // One thread: rate over the thread's CPU time, which other processes on a shared
        // machine disturb far less than wall time. All threads: wall time (the speed-up).
        benchmark::RegisterBenchmark(name.c_str(), run, e.get(), Kind(k), Impl(i))
            ->Unit(benchmark::kMillisecond)
            ->Threads(1);
        if (all > 1)
          benchmark::RegisterBenchmark(name.c_str(), run, e.get(), Kind(k), Impl(i))
              ->Unit(benchmark::kMillisecond)
              ->UseRealTime()
              ->Threads(all);
      }
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);

  std::printf("\n%-28s %7s %10s %10s %7s\n", "Mrays/s", "threads", "ours", "Embree", "ratio");
  for (auto& [name, by_threads] : reporter.rates) {
    std::string impl = name.substr(name.rfind('/') + 1);
    if (impl.rfind("ours", 0) != 0) continue;
    std::string base = name.substr(0, name.rfind('/'));
    std::string ref = base + "/embree" + impl.substr(4);
    for (auto& [threads, ours] : by_threads) {
      double emb = reporter.rates.count(ref) && reporter.rates[ref].count(threads) ? reporter.rates[ref][threads] : 0.0;
      std::printf("%-28s %7d %10.2f %10.2f %7.2f\n", (base + "/" + impl.substr(4) + "x").c_str(), threads, ours,
                  emb, emb > 0.0 ? ours / emb : 0.0);
    }
  }
  benchmark::Shutdown();
  return 0;
}
