// zigzag: adaptive antialiasing ray tracer (Vostryakov & Voloboy 2006, SSE 4-ray packets).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "app/commands.h"
#include "core/error.h"
#include "core/interrupt.h"

int main(int argc, char** argv) {
  CLI::App app{"zigzag: an adaptive antialiasing ray tracer with SSE 4-ray packets"};
  app.set_version_flag("--version", "zigzag 0.1.0");
  app.require_subcommand(1);
  zz::install_interrupt_handlers();
  int exit_code = 0;
  zz::add_render_command(app, exit_code);
  zz::add_view_command(app, exit_code);
  zz::add_analytic_command(app);
  zz::add_merge_command(app);
  zz::add_info_command(app, exit_code);
  // CLI11 answers an unknown command with "A subcommand is required": name it instead.
  if (argc > 1 && argv[1][0] != '-') {
    const std::string command = argv[1];
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      found = found || sub->check_name(command);
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      std::fprintf(stderr, "zigzag: error: unknown command '%s' (the commands: %s; zigzag --help)\n", command.c_str(),
                   known.c_str());
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // `render --aov depth scene.json` reads the scene as the AOV's file and finds no scene.
    const bool aov_ate_the_scene = std::string(e.what()).find("scenes is required") != std::string::npos &&
                                   std::any_of(argv, argv + argc, [](const char* a) { return std::string(a) == "--aov"; });
    const int code = app.exit(e);
    if (aov_ate_the_scene)
      std::fprintf(stderr, "(--aov NAME [FILE] takes the word after NAME as its FILE: put the scene files first, or "
                           "end the options with --)\n");
    return code;
  } catch (const zz::Interrupted& i) {
    std::fprintf(stderr, "%s\n", zz::interrupt_message(i.signal));
    return 128 + i.signal;
  } catch (const zz::UsageError& e) {
    std::fprintf(stderr, "zigzag: error: %s\n", e.what());
    return zz::kUsageExit;
  } catch (const zz::Error& e) {
    std::fprintf(stderr, "zigzag: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    if (zz::out_of_resources(e)) {
      std::fprintf(stderr, "zigzag: error: %s\n", zz::error_text(e).c_str());
      return 1;
    }
    std::fprintf(stderr, "zigzag: internal error: %s\n", e.what());
    return 2;
  }
  return exit_code;
}
