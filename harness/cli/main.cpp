// clipray: reconciles OpenGL rasterization with ray picking. See README.md.

#include <iostream>

#include "Commands.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/scene/InputError.hpp"

int main(int argc, char** argv) {
  CLI::App app{"clipray: reconcile OpenGL rasterization with ray picking"};
  app.require_subcommand(1);
  std::vector<clipray::cli::Subcommand> commands = {clipray::cli::addReconcileCommand(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int status = app.exit(error);
    // CLI11 uses its own codes; clipray promises 2 for every usage error, 0 for --help.
    return status == 0 ? 0 : 2;
  }
  try {
    for (const auto& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const clipray::InputError& error) {
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  } catch (const clipray::gl::BackendError& error) {
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  } catch (const clipray::gl::GlError& error) {
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "clipray: " << error.what() << "\n";
    return 2;
  }
  return 2;
}
