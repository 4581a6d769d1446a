// zigzag: adaptive antialiasing ray tracer (Vostryakov & Voloboy 2006, SSE 4-ray packets).
#include <cstdio>
#include <exception>

#include "app/commands.h"
#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"zigzag: an adaptive antialiasing ray tracer with SSE 4-ray packets"};
  app.set_version_flag("--version", "zigzag 0.1.0");
  app.require_subcommand(1);
  int exit_code = 0;
  zz::add_render_command(app, exit_code);
  zz::add_view_command(app, exit_code);
  zz::add_analytic_command(app);
  zz::add_merge_command(app);
  zz::add_info_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const zz::Error& e) {
    std::fprintf(stderr, "zigzag: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "zigzag: internal error: %s\n", e.what());
    return 2;
  }
  return exit_code;
}
