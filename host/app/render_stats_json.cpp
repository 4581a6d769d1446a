#include "app/render_stats_json.h"

#include <algorithm>

#include "core/worker_arena.h"

namespace zz {

nlohmann::json adaptive_settings_json(const AdaptiveOptions& a) {
  return {{"eps", a.eps},
          {"eps_specular", a.eps_specular >= 0.0f ? nlohmann::json(a.eps_specular) : nlohmann::json("off")},
          {"tables", a.tables->name},
          {"geo_policy", name_of(kGeoPolicies, a.geo_policy)},
          {"filter", name_of(kFilters, a.filter)},
          {"signature", signature_name(a.signature)},
          {"highlights", a.highlights},
          {"textures", a.textures},
          {"footprint", a.footprint},
          {"curvature", a.curvature},
          {"hdr_zones", a.hdr_zones},
          {"geo_orient", a.geo_orient},
          {"geo_zones", a.geo_zones},
          {"split_unflagged", a.split_unflagged},
          {"fill_gaps", a.fill_gaps}};
}

nlohmann::json render_stats_json(const JobRecord& r) {
  const RenderOptions& o = *r.options;
  const RenderSettings& settings = *r.settings;
  const RenderStats& stats = *r.stats;
  const TileRect& region = r.region;
  const double pixels = double(region.width()) * region.height();
  nlohmann::json j;
  j["scene"] = r.scene_name;
  j["camera"] = r.camera;
  j["output"] = r.output;
  j["width"] = settings.width;
  j["height"] = settings.height;
  j["region"] = {region.x0, region.y0, region.x1, region.y1};
  j["pixels"] = int64_t(region.width()) * region.height();
  j["animated"] = r.scene->animated;
  // A --time between frames names none: null (scene_time_s says when).
  j["frame"] = r.frame ? nlohmann::json(*r.frame) : nlohmann::json(nullptr);
  j["scene_time_s"] = r.scene->time;
  j["fps"] = r.scene->fps;
  j["threads"] = worker_threads(settings.threads);
  j["aa"] = name_of(kAaModes, o.aa);
  if (o.aa == AaMode::Uniform) {
    j["spp"] = o.spp;
    j["pattern"] = name_of(kUniformPatterns, o.pattern);
  }
  if (o.aa == AaMode::Adaptive) {
    const AaStats& a = stats.aa;
    nlohmann::json& adaptive = j["adaptive"] = adaptive_settings_json(o.adaptive);
    adaptive.update({{"by_level", {a.per_pixel(a.rays[0]), a.per_pixel(a.rays[1]), a.per_pixel(a.rays[2])}},
                     {"padded", a.per_pixel(a.padded_rays)},  // by_level + padded = rays_per_pixel
                     {"level2_fraction", a.level2_fraction()},
                     {"level3_fraction", a.level3_fraction()},
                     {"vertical_fraction", a.per_pixel(a.vertical_pixels)},
                     {"zones_traced", a.zones_traced},
                     {"zones_interpolated", a.zones_interpolated},
                     {"margin_rays", a.margin_rays},
                     {"geo_fraction", a.per_pixel(a.geo_pixels)},
                     {"hidden_fraction", a.per_pixel(a.hidden_pixels)},
                     {"specular_fraction", a.per_pixel(a.specular_pixels)},
                     {"gap_fraction", a.per_pixel(a.gap_pixels)},
                     // Summed over tiles (CPU seconds across threads): the split of render time.
                     {"time_s", {{"level1_corners", a.seconds_corners},
                                 {"levels_2_3", a.seconds_refine},
                                 {"mitchell_filter", a.seconds_filter}}}});
  }
  j["triangles"] = r.scene->triangle_count();
  j["dropped_degenerate_triangles"] = r.scene->dropped_degenerate;
  j["lights"] = r.scene->lights.size();
  j["max_depth"] = r.scene->max_depth;
  j["effects"] = r.shader->effects().names();
  j["rays_per_pixel"] = double(stats.rays.primary) / pixels;
  // A partial last packet of a tile is padded, and its lanes traced; the lattice pattern
  // also traces each tile's far ring of corners (margin_rays): rays_per_pixel = spp (1 with
  // --aa none) + padded + margin_rays / pixels, as the adaptive section's by_level + padded.
  if (o.aa != AaMode::Adaptive) {
    j["padded"] = double(stats.rays.primary - std::min(stats.rays.primary, stats.samples)) / pixels;
    j["margin_rays"] = stats.margin_samples;
  }
  j["rays"] = {{"primary", stats.rays.primary},
               {"shadow", stats.rays.shadow},
               {"reflection", stats.rays.reflection},
               {"refraction", stats.rays.refraction},
               {"continuation", stats.rays.continuation},
               {"total", stats.rays.total()}};
  j["nan_radiance"] = stats.rays.nan_radiance;  // samples the shader set from NaN to 0: a bug if not 0
  j["layer_limit"] = stats.rays.layer_limit;    // rays cut short behind too many see-through surfaces
  j["capped_radiance"] = stats.rays.capped_radiance;  // samples above the 1e30 cap, +Inf included
  j["bvh"] = {{"nodes", r.bvh->node_count},
              {"leaves", r.bvh->leaf_count},
              {"max_depth", r.bvh->max_depth},
              {"sah_cost", r.bvh->sah_cost},
              {"build_s", r.bvh->build_seconds}};
  j["time_s"] = {{"load", r.times.load},
                 {"bvh", r.times.bvh},
                 {"render", stats.render_seconds},
                 {"frame", r.times.frame},
                 {"write", r.times.write},
                 {"total", r.times.total}};
  j["memory_estimate_bytes"] = r.memory_estimate_bytes;
  j["edges"] = name_of(kEdgeModes, o.edges);
  if (r.edge_times) {
    size_t flagged = 0;
    for (int y = region.y0; y < region.y1; ++y)
      for (int x = region.x0; x < region.x1; ++x) flagged += r.geo->at(x, y);
    j["time_s"]["edges"] = {{"device_wait", r.map_setup.device_wait_s},
                            {"upload", r.map_setup.upload_s},
                            {"prepare", r.map_setup.prepare_s},
                            {"raster", r.edge_times->raster_s},
                            {"compute", r.edge_times->compute_s},
                            {"readback", r.edge_times->readback_s},
                            {"total", r.map_setup.total_s}};
    j["geo_fraction"] = double(flagged) / pixels;
    j["edge_settings"] = {{"supersample", o.edge_ss}, {"normal_angle_deg", o.edge_angle}, {"depth_rel", o.edge_depth}, {"material", o.edge_material}};
    j["vulkan_device"] = r.vulkan_device;
  }
  if (!r.aov_channels.empty())
    j["aov"] = {{"channels", r.aov_channels},
                {"primary_hit_rays", r.aov_rays.total()},
                {"primary_hit_s", r.aov_seconds}};
  j["mrays_per_s"] = stats.render_seconds > 0 ? double(stats.rays.total()) / stats.render_seconds * 1e-6 : 0.0;
  return j;
}

}  // namespace zz
