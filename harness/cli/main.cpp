// clipray: reconciles OpenGL rasterization with ray picking. See README.md.

#include <algorithm>
#include <iostream>

#include "Commands.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/scene/InputError.hpp"

namespace clipray::cli {
std::vector<CommandRegistration>& commandRegistry() {
  static std::vector<CommandRegistration> registry;
  return registry;
}
}  // namespace clipray::cli

int main(int argc, char** argv) {
  CLI::App app{"clipray: reconcile OpenGL rasterization with ray picking"};
  app.require_subcommand(1);
  auto registry = clipray::cli::commandRegistry();
  std::sort(registry.begin(), registry.end(),
            [](const auto& a, const auto& b) { return a.order < b.order; });
  std::vector<std::pair<CLI::App*, clipray::cli::CommandRunner>> commands;
  for (const auto& registration : registry) {
    CLI::App* sub = app.add_subcommand(registration.name, registration.description);
    commands.emplace_back(sub, registration.factory(*sub));
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    // CLI11 uses its own codes; clipray promises 2 for every usage error, 0 for --help.
    return status == 0 ? 0 : 2;
  }
  try {
    for (const auto& [sub, run] : commands) {
      if (sub->parsed()) return run();
    }
  } catch (const clipray::InputError& error) {
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  } catch (const clipray::gl::BackendError& error) {
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    // GL errors and anything unforeseen: a message and status 2, never a crash.
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  }
  return 2;
}
