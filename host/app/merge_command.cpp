// `zigzag merge PART.exr... -o OUT`: the EXR parts of one frame (`zigzag render
// --region`) assembled into the whole frame, bit-identical to a full-frame render.
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/option_checks.h"
#include "app/output_paths.h"
#include "core/error.h"
#include "render/film_merge.h"
#include "render/image_io.h"

namespace zz {

namespace {

struct MergeOptions {
  std::vector<std::string> parts;
  std::string output;
};

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
      preflight_output("-o", o->output, true);
      check_not_an_input("-o", o->output, o->parts, "one of the parts,");
    });
    std::vector<FilmPart> parts;
    parts.reserve(o->parts.size());
    for (const std::string& p : o->parts) parts.push_back({p, read_film(p)});
    FilmFile merged = merge_films(parts);
    parts.clear();  // the parts' memory before the output's display bytes
    // The AOV layers go into an EXR; any other output is the colour alone.
    if (!holds_extra_channels(o->output)) merged.film.channels.clear();
    write_film(o->output, merged.film, merged.tonemap, merged.attributes);
  });
}

}  // namespace zz
