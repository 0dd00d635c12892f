#include "cli/usage_hint.h"

#include <algorithm>
#include <string_view>

#include "frontend/spelling.h"

namespace rcxc::cli {
namespace {

// The command's options and those of the commands it is under (`rcxc nxt
// --port P info`: --port is nxt's).
std::vector<std::string> long_options(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::App* at = &app; at; at = at->get_parent())
    for (const CLI::Option* option : at->get_options())
      for (const std::string& name : option->get_lnames()) out.push_back("--" + name);
  return out;
}

std::vector<std::string> command_names(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    out.push_back(sub->get_name());
  return out;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// `--port usb`: the word after such an option is its value, no command.
bool takes_value(const CLI::App& app, const std::string& word) {
  if (word.find('=') != std::string::npos) return false;
  for (const CLI::App* at = &app; at; at = at->get_parent())
    if (const CLI::Option* option = at->get_option_no_throw(word)) return option->get_items_expected_max() > 0;
  return false;
}

// Words a user types for an action that has another name, checked before
// the spelling: `rcxc nxt serve` is the virtual brick, not a misspelt
// `start`. `command` is the path after rcxc ("nxt").
struct Synonym {
  std::string_view command, word, says;
};
constexpr Synonym kSynonyms[] = {
    {"nxt", "serve", "a virtual NXT is served by 'rcxc nxt brick --pty'"},
    {"nxt", "server", "a virtual NXT is served by 'rcxc nxt brick --pty'"},
    {"nxt", "virtual", "a virtual NXT is served by 'rcxc nxt brick --pty'"},
    {"nxt", "emulator", "a virtual NXT is served by 'rcxc nxt brick --pty'"},
    {"nxt", "delete", "a file on the brick is deleted by 'rcxc nxt rm NAME'"},
    {"nxt", "remove", "a file on the brick is deleted by 'rcxc nxt rm NAME'"},
    {"nxt", "list", "the brick's files are listed by 'rcxc nxt ls'"},
    {"nxt", "dir", "the brick's files are listed by 'rcxc nxt ls'"},
    {"nxt", "run", "a program on the brick is started by 'rcxc nxt start NAME'"},
    {"nxt", "put", "a file goes to the brick with 'rcxc nxt upload FILE'"},
    {"nxt", "send", "a file goes to the brick with 'rcxc nxt upload FILE'"},
    {"nxt", "get", "a file comes from the brick with 'rcxc nxt download NAME'"},
    {"nxt", "fetch", "a file comes from the brick with 'rcxc nxt download NAME'"},
    {"nxt", "version", "the firmware version is in 'rcxc nxt info'"},
    {"nxt", "firmware", "the firmware version is in 'rcxc nxt info'"},
    {"nxt", "beep", "a tone is played by 'rcxc nxt tone HZ MS'"},
    {"nxt", "format", "every file on the brick is deleted by 'rcxc nxt erase-all --yes'"},
    {"nxt", "wipe", "every file on the brick is deleted by 'rcxc nxt erase-all --yes'"},
    {"nxt", "bt", "Bluetooth is switched by 'rcxc nxt bluetooth on|off'"},
    {"nxt", "boot", "Boot erases the firmware: rcxc has no action for it (docs/nxt.md; raw can send it)"},
};

// "nxt mailbox" for rcxc nxt mailbox: the command's words after rcxc.
std::string command_path(const CLI::App& app) {
  std::string path;
  for (const CLI::App* at = &app; at && at->get_parent(); at = at->get_parent())
    path = at->get_name() + (path.empty() ? "" : " " + path);
  return path;
}

}  // namespace

std::optional<std::string> option_without_value(const std::vector<std::string>& words) {
  for (const std::string& w : words) {
    if (w == "--") break;
    if (w.size() > 3 && w.starts_with("--") && w.find('=') == w.size() - 1) {
      std::string name = w.substr(0, w.size() - 1);
      return w + ": nothing after '=' (give " + name + "=VALUE, or leave " + name + " out)";
    }
  }
  return std::nullopt;
}

bool hint_explains(const MisspellingHint& hint, const std::string& unexpected) {
  return hint.command || unexpected == hint.word || unexpected == hint.value;
}

std::optional<MisspellingHint> misspelling_hint(const CLI::App& app, const std::vector<std::string>& words) {
  // The deepest command the words name, read as the parser reads them (the
  // parser's own record stops short when it fails inside a command).
  const CLI::App* where = &app;
  auto from = words.begin();
  for (auto w = words.begin(); w != words.end(); ++w) {
    if (w->empty()) continue;
    if ((*w)[0] == '-') {
      if (takes_value(*where, *w) && w + 1 != words.end()) ++w;
      continue;
    }
    const CLI::App* sub = nullptr;
    for (const CLI::App* s : where->get_subcommands([](const CLI::App*) { return true; }))
      if (s->get_name() == *w) sub = s;
    if (!sub) break;
    where = sub;
    from = w + 1;
  }
  const std::vector<std::string> options = long_options(*where);
  const std::vector<std::string> commands = command_names(*where);
  bool first_word = true;
  for (auto w = words.begin(); w != words.end(); ++w) {
    if (w->rfind("--", 0) == 0 && w->size() > 2) {
      std::string name = w->substr(0, w->find('='));
      if (contains(options, name)) {
        if (takes_value(*where, *w) && w + 1 != words.end()) ++w;
        continue;
      }
      if (auto near = frontend::closest_name(name, options)) {
        MisspellingHint hint{*w, "unknown option '" + name + "': did you mean '" + *near + "'?", false, std::nullopt};
        if (takes_value(*where, *near) && w->find('=') == std::string::npos && w + 1 != words.end())
          hint.value = *(w + 1);
        return hint;
      }
      continue;
    }
    if (!w->empty() && (*w)[0] == '-') {
      if (takes_value(*where, *w) && w + 1 != words.end()) ++w;
      continue;
    }
    if (w < from || w->empty() || !first_word) continue;
    // The first plain word after the command names the action, where the
    // command has actions.
    first_word = false;
    if (commands.empty() || contains(commands, *w)) continue;
    std::string what = where->get_parent() ? "action" : "command";
    for (const Synonym& synonym : kSynonyms)
      if (synonym.command == command_path(*where) && synonym.word == *w)
        return MisspellingHint{*w, "unknown " + what + " '" + *w + "': " + std::string(synonym.says), true,
                               std::nullopt};
    if (auto near = frontend::closest_name(*w, commands))
      return MisspellingHint{*w, "unknown " + what + " '" + *w + "': did you mean '" + *near + "'?", true, std::nullopt};
    // CLI11 says only "A subcommand is required", as if none were given.
    return MisspellingHint{*w, "unknown " + what + " '" + *w + "': the " + what + "s are listed below", true,
                           std::nullopt};
  }
  return std::nullopt;
}

std::string action_list(const CLI::App& command) {
  const std::string path = "rcxc " + command_path(command);
  std::string out = "the actions of " + path + ":";
  std::size_t line = out.size();
  const std::vector<std::string> names = command_names(command);
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::string word = " " + names[i] + (i + 1 < names.size() ? "," : "");
    if (line + word.size() > 78) {
      out += "\n ";
      line = 1;
    }
    out += word;
    line += word.size();
  }
  return out + "\n'rcxc help " + command_path(command) + "' says what each does\n";
}

bool is_missing_action(const CLI::ParseError& e) {
  return dynamic_cast<const CLI::RequiredError*>(&e) && std::string_view(e.what()) == "A subcommand is required";
}

std::string parse_error_text(const CLI::ParseError& e) {
  if (is_missing_action(e)) return "an action is required: the actions are listed below";
  std::string text = e.what();
  if (!dynamic_cast<const CLI::ArgumentMismatch*>(&e)) return text;
  // "NAME: 1 required TEXT:{0,1,2,s} missing", as CLI11 words an option
  // given without its value (`rcxc run p.nqc -D`).
  const std::string required = ": 1 required ", missing = " missing";
  if (std::size_t at = text.find(required);
      at != std::string::npos && text.ends_with(missing) && at + required.size() <= text.size() - missing.size()) {
    std::string type = text.substr(at + required.size(), text.size() - missing.size() - at - required.size());
    std::size_t choices = type.find(":{");
    return text.substr(0, at) + " needs a value" +
           (choices != std::string::npos && type.ends_with("}")
                ? ": one of " + type.substr(choices + 2, type.size() - choices - 3)
                : "");
  }
  // "NAME: At Most N required but received M", as CLI11 words an option
  // given more often than it takes.
  const std::string at_most = ": At Most ", received = " required but received ";
  std::size_t at = text.find(at_most), got = text.find(received);
  if (at == std::string::npos || got == std::string::npos || got < at) return text;
  std::string most = text.substr(at + at_most.size(), got - at - at_most.size());
  std::string times = text.substr(got + received.size());
  return text.substr(0, at) + " given " + times + " times: it takes " + (most == "1" ? "one" : "at most " + most);
}

}  // namespace rcxc::cli
