#include "PickScript.hpp"

#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "clipray/InputError.hpp"
#include "clipray/io/InputFile.hpp"

namespace clipray::demo {

namespace {

class LineReader {
 public:
  LineReader(const std::string& path, int line, const std::string& text)
      : where_(path + ":" + std::to_string(line) + ": "), words_(text) {}

  std::string word() {
    std::string w;
    words_ >> w;
    return w;
  }

  double number(const char* what) {
    const std::string w = word();
    if (w.empty()) fail(std::string("missing ") + what);
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(w, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != w.size() || !std::isfinite(value)) {
      fail(std::string(what) + ": expected a number, got \"" + w + "\"");
    }
    return value;
  }

  void end() {
    const std::string extra = word();
    if (!extra.empty()) fail("unexpected \"" + extra + "\" at the end of the line");
  }

  [[noreturn]] void fail(const std::string& message) const { throw InputError(where_ + message); }

 private:
  std::string where_;
  std::istringstream words_;
};

}  // namespace

std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& path) {
  std::vector<ScriptCommand> commands;
  std::istringstream lines(text);
  std::string raw;
  int lineNumber = 0;
  while (std::getline(lines, raw)) {
    ++lineNumber;
    const std::string content = raw.substr(0, raw.find('#'));
    LineReader reader(path, lineNumber, content);
    const std::string verb = reader.word();
    if (verb.empty()) continue;
    ScriptCommand command;
    command.line = lineNumber;
    if (verb == "resize") {
      command.kind = ScriptCommand::Kind::Resize;
      command.a = {reader.number("width"), reader.number("height")};
      if (command.a.x < 1 || command.a.y < 1 || command.a.x > 16384 || command.a.y > 16384 ||
          command.a != glm::floor(command.a)) {
        reader.fail("resize: expected whole numbers from 1 to 16384");
      }
    } else if (verb == "click") {
      command.kind = ScriptCommand::Kind::Click;
      command.a = {reader.number("x"), reader.number("y")};
    } else if (verb == "drag") {
      command.kind = ScriptCommand::Kind::Drag;
      const std::string button = reader.word();
      if (button != "left" && button != "right") {
        reader.fail("drag: expected left or right, got \"" + button + "\"");
      }
      command.rightButton = button == "right";
      command.a = {reader.number("x0"), reader.number("y0")};
      command.b = {reader.number("x1"), reader.number("y1")};
    } else if (verb == "scroll") {
      command.kind = ScriptCommand::Kind::Scroll;
      command.steps = reader.number("steps");
    } else if (verb == "key") {
      command.kind = ScriptCommand::Kind::Key;
      const std::string key = reader.word();
      if (key.size() != 1 ||
          !std::strchr(kScriptKeys, std::tolower(static_cast<unsigned char>(key[0])))) {
        std::string keys;
        for (const char* k = kScriptKeys; *k != '\0'; ++k) {
          keys += (keys.empty() ? "" : ", ") + std::string(1, *k);
        }
        reader.fail("key: expected one of " + keys + ", got \"" + key + "\"");
      }
      command.key = static_cast<char>(std::tolower(static_cast<unsigned char>(key[0])));
    } else {
      reader.fail("unknown command \"" + verb +
                  "\"; expected one of: resize, click, drag, scroll, key");
    }
    reader.end();
    commands.push_back(command);
  }
  return commands;
}

std::vector<ScriptCommand> loadScript(const std::string& path) {
  const std::string text = readInputFile(path, kMaxScriptFileBytes, "script");
  requireNoNulBytes(text, path);
  return parseScript(text, path);
}

}  // namespace clipray::demo
