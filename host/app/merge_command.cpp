// `zigzag merge PART.exr... -o OUT`: the EXR parts of one frame (`zigzag render
// --region`) assembled into the whole frame, bit-identical to a full-frame render.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/option_checks.h"
#include "app/output_paths.h"
#include "core/error.h"
#include "render/film_merge.h"
#include "render/image_io.h"
#include "render/memory_budget.h"

namespace zz {

namespace {

struct MergeOptions {
  std::vector<std::string> parts;
  std::string output;
};

// A film of w x h with `channels` AOV layers: radiance, the rays and level bytes, the layers.
uint64_t film_bytes(uint64_t pixels, size_t channels) { return pixels * (sizeof(glm::vec3) + 2 + 4 * channels); }

// Peak memory of the merge: the frame and its interleaved copy for the writer (or its
// display bytes), and the largest part with the interleaved buffer it is read through.
uint64_t merge_bytes(const std::vector<FilmPart>& headers, bool exr) {
  const Film& first = headers.front().file.film;
  const size_t channels = first.channels.size();
  const uint64_t frame = uint64_t(first.frame_width) * uint64_t(first.frame_height);
  uint64_t largest = 0;
  for (const FilmPart& p : headers) largest = std::max(largest, uint64_t(p.file.film.width) * uint64_t(p.file.film.height));
  const uint64_t interleaved = 4 * (3 + channels);
  return film_bytes(frame, channels) + frame * (exr ? interleaved : 3) + film_bytes(largest, channels) +
         largest * interleaved;
}

}  // namespace

void add_merge_command(CLI::App& app) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "merge", "Assemble the EXR parts of a frame (zigzag render --region) into the whole frame");
  cmd->add_option("parts", o->parts, "EXR parts; together they must cover the frame exactly once")->required();
  cmd->add_option("-o,--output", o->output, "Output image (.png = display image, .exr = linear radiance and the parts' AOV layers)")
      ->required()
      ->check(non_empty("-o"));
  cmd->callback([o] {
    as_usage_checks([&] {  // before the parts are read: a bad invocation costs nothing
      (void)environment_memory_limit();  // a malformed $ZIGZAG_MEMORY_LIMIT
      // A file name, not a pattern: `merge -o m_{scene}.png` wrote a file of that name. Any
      // '{' is one, as render's -o reads it: a placeholder, or an unknown one it refuses.
      if (o->output.find('{') != std::string::npos)
        throw UsageError("-o " + o->output + ": merge writes one file, named in full ({scene}, {camera} and {frame} "
                         "are placeholders of zigzag render's -o)");
      preflight_output("-o", o->output, true);
      check_not_an_input("-o", o->output, o->parts, "one of the parts,");
    });
    // The parts' headers first: a set that does not tile one frame of one render is
    // refused before any pixel is read, and the frame is filled one part at a time, so the
    // merge holds the frame and one part, not every part at once.
    std::vector<FilmPart> headers;
    headers.reserve(o->parts.size());
    for (const std::string& p : o->parts) headers.push_back({p, read_film_header(p)});
    check_film_parts(headers);
    const std::vector<std::string> devices = devices_of(headers);
    const auto joined = [&](const char* separator) {
      std::string all;
      for (const std::string& d : devices) all += (all.empty() ? "" : separator) + d;
      return all;
    };
    if (devices.size() > 1) {
      std::fprintf(stderr,
                   "zigzag: warning: the parts' visibility maps were made on different Vulkan devices (%s); "
                   "a device may flag a few edge pixels differently, so the merge can differ there from a "
                   "one-device render\n",
                   joined(", ").c_str());
    }
    check_memory(merge_bytes(headers, holds_extra_channels(o->output)), "merging these parts");
    FilmFile merged = empty_frame(headers.front().file);
    if (devices.size() > 1) merged.attributes[kDeviceAttribute] = joined("; ");
    for (const FilmPart& p : headers) {
      const FilmFile part = read_film(p.name);
      if (!same_film_header(part, p.file)) throw Error("merge: " + p.name + " changed while the parts were merged");
      paste_part(merged, part.film);
    }
    // The AOV layers go into an EXR; any other output is the colour alone.
    if (!holds_extra_channels(o->output)) merged.film.channels.clear();
    write_film(o->output, merged.film, merged.tonemap, merged.attributes);
  });
}

}  // namespace zz
