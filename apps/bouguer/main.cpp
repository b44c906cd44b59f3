// bouguer: the command line. A thin shell around the library: parse, dispatch, report errors
// as one line. Exit codes: 0 success, 1 bad input or failed work, 2 bad command line.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer_version.h"
#include "commands.h"

namespace {

std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// CLI11 reports an unknown command word as a missing subcommand; name the word instead.
std::string describe(const CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
  if (argc < 2 || argv[1][0] == '-') return one_line(e.what());
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  const std::string word = argv[1];
  if (std::find(names.begin(), names.end(), word) != names.end()) return one_line(e.what());
  const auto near = bouguer::nearest_name(word, names);
  return fmt::format("unknown command '{}'{}", word, near ? fmt::format("; did you mean '{}'?", *near) : "");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Bouguer: spectral rendering of transparent, absorbing matter (glass, gems, liquids).", "bouguer"};
  app.set_version_flag("--version", "bouguer " BOUGUER_VERSION);
  app.require_subcommand(1);
  const std::vector<bouguer::cli::Command> commands = {bouguer::cli::add_render_command(app),
                                                       bouguer::cli::add_compare_command(app),
                                                       bouguer::cli::add_color_command(app),
                                                       bouguer::cli::add_material_command(app),
                                                       bouguer::cli::add_report_command(app)};

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "bouguer: error: {} (see 'bouguer --help')\n", describe(app, argc, argv, e));
    return 2;
  }

  try {
    for (const auto& command : commands)
      if (command.app->parsed()) return command.run();
    return 2;
  } catch (const bouguer::Error& e) {
    fmt::print(stderr, "bouguer: error: {}\n", one_line(e.what()));
    if (dynamic_cast<const bouguer::UsageError*>(&e)) return 2;  // e.g. an output path that cannot be written
  } catch (const std::bad_alloc&) {
    // The readers and the render check their sizes against the memory available first, so this
    // is memory taken by something else meanwhile, or an estimate that fell short.
    fmt::print(stderr, "bouguer: error: out of memory (try a smaller resolution or scene, or free memory)\n");
  } catch (const std::exception& e) {
    fmt::print(stderr, "bouguer: internal error: {}\n", one_line(e.what()));
  }
  return 1;
}
