// Each `zigzag` subcommand registers itself on the CLI11 app; its callback stores the
// process exit code in `exit_code` (user errors are thrown as zz::Error instead).
#pragma once

#include <CLI/CLI.hpp>

namespace zz {

void add_render_command(CLI::App& app, int& exit_code);
void add_view_command(CLI::App& app, int& exit_code);
void add_analytic_command(CLI::App& app);
void add_merge_command(CLI::App& app);
void add_info_command(CLI::App& app, int& exit_code);

}  // namespace zz
