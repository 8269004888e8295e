#include "app.hpp"

#include <cstdio>
#include <new>
#include <string_view>

#include "common.hpp"
#include "dq/io/file.hpp"

namespace dq::cli {

std::unique_ptr<CLI::App> make_app(Arguments& a) {
  auto app = std::make_unique<CLI::App>("dqkit: rigid transforms with dual quaternions, for 3D character hierarchies");
  app->require_subcommand(1);
  // Usage errors start with "dqkit: " as the others do (a script greps standard error for it).
  app->failure_message([](const CLI::App* failed, const CLI::Error& e) { return "dqkit: " + CLI::FailureMessage::simple(failed, e); });
  app->set_version_flag("--version", "dqkit 0.1.0");
  for (const Command& c : commands()) {
    CLI::App* sub = app->add_subcommand(std::string(c.name), std::string(c.description));
    a.commands.emplace_back(sub, c.define(*sub));
  }
  return app;
}

int run_command(const Arguments& a) {
  for (const auto& [sub, runner] : a.commands)
    if (sub->parsed()) return runner();
  return 1;  // unreachable: CLI11 requires one subcommand
}

namespace {
int fail(const std::string& message) {
  std::fprintf(stderr, "dqkit: %s\n", printable(message).c_str());
  return 1;
}
}  // namespace

int run_tool(int argc, char** argv) {
  try {
    Arguments args;
    const auto app = make_app(args);
    // An option before any command is named (CLI11 would say only that a command is required).
    if (argc > 1 && argv[1][0] == '-') {
      const std::string_view first = argv[1];
      if (first != "-h" && first != "--help" && first != "--version")
        return fail("unknown option '" + std::string(first) + "' before the command (dqkit COMMAND [OPTIONS]; see dqkit --help)");
    }
    // An unknown command is named (CLI11 would say only that an argument was not expected).
    if (argc > 1 && argv[1][0] != '-') {
      bool known = false;
      std::string names;
      for (const Command& c : commands()) {
        known = known || c.name == argv[1];
        names += (names.empty() ? "" : ", ") + std::string(c.name);
      }
      if (!known) return fail("unknown command '" + std::string(argv[1]) + "' (commands: " + names + "; see dqkit --help)");
    }
    try {
      app->parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      return app->exit(e);
    }
    remove_temporary_files_on_signals();
    return run_command(args);
  } catch (const Failure& e) {
    return fail(e.what());
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what());
  } catch (...) {
    return fail("internal error (unknown exception)");
  }
}

}  // namespace dq::cli
