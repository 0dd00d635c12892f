#include "cli/nqc_mode.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>
#include <tuple>
#include <sstream>
#include <variant>

#include <fmt/format.h>

#include "backend/compile.h"
#include "backend/nqc_listing.h"
#include "savefile/savefile.h"
#include "cli/program_loader.h"
#include "cli/version.h"
#include "frontend/frontend.h"
#include "frontend/parse.h"
#include "frontend/preprocess.h"
#include "link/download.h"
#include "link/remote.h"
#include "link/transport.h"
#include "rcx/file_read.h"
#include "rcx/image.h"
#include "stdlib/stdlib.h"

namespace rcxc::cli {
namespace {

// Where -E and -L send their text: standard output without a file name.
struct TextTarget {
  std::string file;  // "" = standard output
};

// One step of the command line, run in the order given: nqc compiles the
// file when it reaches it and runs each action where it stands.
struct SourceStep {
  std::string name;  // "-" = standard input
};
struct ActionStep {
  std::string name;                // "-run", "-pgm", ...
  std::vector<std::string> words;  // its arguments
};
// A command-line error found at this point: what came before still runs.
struct UsageStep {
  std::string message;
};
using Step = std::variant<SourceStep, ActionStep, UsageStep>;

struct NqcOptions {
  frontend::Options frontend;
  bool binary = false;    // -b: the input is an .rcx image
  bool download = false;  // -d
  bool source_in_listing = false;
  bool lasm_listing = false;  // -c: the listing in LASM's layout
  bool verbose = false;
  bool quiet = false;
  std::optional<TextTarget> errors;   // -E
  std::optional<TextTarget> listing;  // -L
  std::optional<std::string> output;  // -O
  std::optional<std::string> text_output;  // -R
  std::optional<std::string> port;    // -S
  std::vector<Step> steps;
};

// Actions and how many arguments each takes.
struct ActionSpec {
  std::string_view name;
  int arguments;
};
constexpr ActionSpec kActions[] = {
    {"-run", 0},     {"-pgm", 1},   {"-datalog", 0}, {"-datalog_full", 0}, {"-near", 0},  {"-far", 0},
    {"-watch", 1},   {"-firmware", 1}, {"-firmfast", 1}, {"-sleep", 1},     {"-msg", 1},   {"-raw", 1},
    {"-remote", 2},  {"-clear", 0}, {"-api", 0},     {"-help", 0},
};

// nqc's targets other than the RCX: named so the refusal can say why.
constexpr std::string_view kOtherTargets[] = {"RCX2", "CM", "Scout", "Spy", "Swan", "Spybot"};

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

bool is_number(std::string_view s) {
  int value = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return ec == std::errc() && end == s.data() + s.size();
}

// Reads one option (a word before the source file that is not an action).
// Returns what is wrong with it, or "".
std::string read_option(const std::string& word, NqcOptions& o) {
  const char letter = word.size() > 1 ? word[1] : '\0';
  const std::string value = word.size() > 2 ? word.substr(2) : std::string();
  auto flag = [&](bool& b) {
    if (!value.empty()) return fmt::format("unknown option '{}'", word);
    b = true;
    return std::string();
  };
  auto needs_value = [&](std::optional<std::string>& where, std::string_view what) {
    if (value.empty()) return fmt::format("-{} needs {} right after it (-{}{})", letter, what, letter, what);
    where = value;
    return std::string();
  };
  switch (letter) {
    case 'T':
      if (equal_ignoring_case(value, "RCX")) return "";
      for (auto other : kOtherTargets)
        if (equal_ignoring_case(value, other))
          return fmt::format("target '{}' is not supported: rcxc compiles for the RCX (-TRCX) only", value);
      return fmt::format("unknown target '{}' (rcxc compiles for the RCX: -TRCX)", value);
    case 'd': return flag(o.download);
    case 'n': return flag(o.frontend.no_stdlib);
    case 'b': return flag(o.binary);
    case 's': return flag(o.source_in_listing);
    case 'v': return flag(o.verbose);
    case 'q': return flag(o.quiet);
    case 'c': return flag(o.lasm_listing);
    case 'x': {  // no packet header: the towers rcxc drives always use one
      bool ignored = false;
      return flag(ignored);
    }
    case 'D': {
      std::string name = value.substr(0, value.find('='));
      if (name.empty()) return "-D needs a macro name (-DNAME or -DNAME=VALUE)";
      // nqc takes -Dtask=1 and never expands it (its lexer reads keywords
      // first); defined here it would replace every `task`.
      if (frontend::not_a_macro_name(name)) return "";
      // nqc defines -DNAME as empty, not as 1.
      o.frontend.defines.emplace_back(name, value.find('=') == std::string::npos ? "" : value.substr(name.size() + 1));
      return "";
    }
    case 'U':
      if (value.empty()) return "-U needs a macro name (-UNAME)";
      o.frontend.undefines.push_back(value);
      return "";
    case 'I':
      if (value.empty()) return "-I needs a folder right after it (-IPATH)";
      o.frontend.include_dirs.push_back(value);
      return "";
    case 'E': o.errors = TextTarget{value}; return "";
    case 'L': o.listing = TextTarget{value}; return "";
    case 'O': return needs_value(o.output, "FILE");
    case 'R': return needs_value(o.text_output, "FILE");
    case 'S': return needs_value(o.port, "PORT");
    case 'f':
    case 'w':
      // Firmware chunk size and download wait: rcxc's link sizes its blocks
      // and timeouts itself (docs/link.md), so the numbers are checked only.
      if (!is_number(value)) return fmt::format("-{} needs a number right after it (-{}N)", letter, letter);
      return "";
    default: return fmt::format("unknown option '{}'", word);
  }
}

// nqc reads NQC_OPTIONS as if its words came first on the command line.
std::vector<std::string> with_environment_options(const std::vector<std::string>& args) {
  std::vector<std::string> all;
  if (const char* env = std::getenv("NQC_OPTIONS")) {
    std::istringstream words(env);
    all.assign(std::istream_iterator<std::string>(words), std::istream_iterator<std::string>());
  }
  all.insert(all.end(), args.begin(), args.end());
  return all;
}

NqcOptions parse_command_line(const std::vector<std::string>& args) {
  NqcOptions o;
  bool seen_source = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (word == "-" || word.empty() || word[0] != '-') {
      if (seen_source) {
        o.steps.push_back(UsageStep{fmt::format("a second source file '{}': nqc takes one per call", word)});
        return o;
      }
      seen_source = true;
      o.steps.push_back(SourceStep{word});
      continue;
    }
    auto action = std::find_if(std::begin(kActions), std::end(kActions), [&](const ActionSpec& a) { return a.name == word; });
    if (action != std::end(kActions)) {
      if (i + static_cast<std::size_t>(action->arguments) >= args.size()) {
        o.steps.push_back(UsageStep{fmt::format("{} needs {} argument{}", word, action->arguments,
                                                action->arguments == 1 ? "" : "s")});
        return o;
      }
      ActionStep step{word, {}};
      for (int k = 0; k < action->arguments; ++k) step.words.push_back(args[++i]);
      o.steps.push_back(std::move(step));
      continue;
    }
    if (!o.steps.empty()) {
      o.steps.push_back(UsageStep{fmt::format("option '{}' after {}: options come first", word,
                                              seen_source ? "the source file" : "an action")});
      return o;
    }
    if (std::string bad = read_option(word, o); !bad.empty()) {
      o.steps.push_back(UsageStep{bad});
      return o;
    }
  }
  if (o.steps.empty()) o.steps.push_back(UsageStep{"nothing to do: give a source file or an action"});
  if (const char* env = std::getenv("NQC_INCLUDE"); env && *env) o.frontend.include_dirs.push_back(env);
  return o;
}

// The files named on the command line that the call may write: -E, -L, -O
// and -R, with their letters.
std::vector<std::pair<char, std::string>> named_outputs(const NqcOptions& o) {
  std::vector<std::pair<char, std::string>> out;
  if (o.errors && !o.errors->file.empty()) out.emplace_back('E', o.errors->file);
  if (o.listing && !o.listing->file.empty()) out.emplace_back('L', o.listing->file);
  if (o.output) out.emplace_back('O', *o.output);
  if (o.text_output) out.emplace_back('R', *o.text_output);
  return out;
}

// An output that is the source file, or two outputs in one file: nqc
// empties the program, or keeps only what was written last.
std::optional<std::string> clashing_outputs(const NqcOptions& o) {
  std::string source;
  for (const Step& step : o.steps)
    if (auto* s = std::get_if<SourceStep>(&step); s && s->name != "-") source = s->name;
  auto outputs = named_outputs(o);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [letter, file] = outputs[i];
    if (!source.empty() && savefile::same_file(file, source))
      return fmt::format("refusing to write {} (-{}): it is the source file", file, letter);
    for (std::size_t j = 0; j < i; ++j)
      if (savefile::same_file(file, outputs[j].second))
        return fmt::format("-{} and -{} both name {}: one would overwrite the other", outputs[j].first, letter, file);
  }
  return std::nullopt;
}

void print_help() {
  std::cout << fmt::format(
      "rcxc {} in nqc mode: nqc 3.1's command line (docs/nqc.md)\n"
      "usage: nqc [options] [actions] [- | FILE] [actions]\n"
      "  -             read the program from standard input\n"
      "options (before the file):\n"
      "  -T<target>    RCX only (other targets are refused)\n"
      "  -d            download the program into the RCX\n"
      "  -n            do not include the API file rcx.nqh\n"
      "  -b            FILE is an .rcx image, not source\n"
      "  -D<sym>[=<v>] define a macro (empty without =<v>)   -U<sym>  undefine it\n"
      "  -E[<file>]    errors to <file> (standard output without one)\n"
      "  -R<file>      text the actions print (datalog, ...) to <file>\n"
      "  -I<path>      search <path> for include files (NQC_INCLUDE is searched last)\n"
      "  -L[<file>]    listing to <file> (standard output without one); -s adds the source,\n"
      "                -c writes it for LASM (operands as numbers, labels for branches)\n"
      "  -O<file>      the image file (default: FILE's name with .rcx, unless -L or -d)\n"
      "  -S<port>      tower: usb, serial or a device (default: RCX_PORT, else usb)\n"
      "  -v -q         verbose link / no download sound;  -x -f<n> -w<ms> are accepted\n"
      "actions (run in order, before or after the file):\n"
      "  -run  -pgm <n>  -datalog  -datalog_full  -near  -far  -watch <hh:mm|now>\n"
      "  -firmware <file>  -firmfast <file>  -sleep <min>  -msg <n>  -raw <hex>  -clear\n"
      "  -api (print rcx.nqh)  -help\n"
      "NQC_OPTIONS is read as if its words came first. Exit codes: 0 done, 243 compile errors or an\n"
      "unreadable file, 244 bad command line, 253 the RCX did not answer, 255 no tower.\n",
      kVersion);
}

// Where a diagnostic is in the user's text: a token from a macro body is
// reported where the macro was used, as nqc does.
SourceLoc user_location(const SourceLoc& loc, const SourceManager& sm) {
  auto expansions = sm.expansion_notes(loc);
  return expansions.empty() ? loc : expansions.back().span.begin;
}

std::string file_label(std::uint32_t file, const SourceManager& sm) {
  if (file == 0) return sm.path(file);
  // nqc names an included file as the #include spells it (`sub/parts.nqh`),
  // and a tool opens that name from the program's folder or an -I folder:
  // the file's own name alone (`parts.nqh`) is not there. The spelling is
  // read back from the #include line; one a macro names gets the file's
  // own name.
  std::string own = std::filesystem::path(sm.path(file)).filename().string();
  SourceSpan site = sm.include_site(file);
  if (!site.begin.valid() || site.begin.file >= sm.size()) return own;
  std::string_view line = sm.line(site.begin.file, site.begin.line);
  std::size_t open = line.find_first_of("\"<", site.begin.column == 0 ? 0 : site.begin.column - 1);
  if (open == std::string_view::npos) return own;
  std::size_t close = line.find(line[open] == '"' ? '"' : '>', open + 1);
  if (close == std::string_view::npos) return own;
  std::string spelled(line.substr(open + 1, close - open - 1));
  std::string found = std::filesystem::path(sm.path(file)).generic_string();
  bool names_it = !spelled.empty() && found.size() >= spelled.size() &&
                  found.compare(found.size() - spelled.size(), spelled.size(), spelled) == 0;
  return names_it ? spelled : own;
}

class Session {
 public:
  explicit Session(NqcOptions options) : o_(std::move(options)) {}

  int run() {
    // Checked before any file is opened: opening an -E or -R file that is
    // the program would empty it.
    if (auto clash = clashing_outputs(o_)) return perform(UsageStep{*clash});
    // As nqc, an -E or -R file that cannot be written stops the call before
    // anything is compiled or sent: the text would have nowhere to go.
    if (o_.errors && !o_.errors->file.empty() && !std::ofstream(o_.errors->file, std::ios::app))
      return perform(UsageStep{"cannot write the error file '" + o_.errors->file + "' (-E)"});
    if (o_.text_output) {
      text_file_ = std::make_unique<std::ofstream>(*o_.text_output, std::ios::binary);
      if (!*text_file_) return perform(UsageStep{"cannot write the output file '" + *o_.text_output + "' (-R)"});
    }
    for (const Step& step : o_.steps) {
      int code = std::visit([this](const auto& s) { return perform(s); }, step);
      if (code != kNqcExitOk) return code;
    }
    return kNqcExitOk;
  }

 private:
  int perform(const UsageStep& s) {
    std::cerr << "rcxc (as nqc): " << s.message << "\n"
              << "usage error: 'nqc -help' lists the options\n";
    return kNqcExitUsage;
  }

  // Errors go where -E says; an -E file is written even when there are none.
  // Should it fail now (a full disk), they go to stderr, and the call fails.
  bool report_errors(const std::string& text) {
    if (!o_.errors) {
      std::cerr << text;
    } else if (o_.errors->file.empty()) {
      std::cout << text;
    } else if (auto unwritten = savefile::write_file_atomically(o_.errors->file, text)) {
      std::cerr << text << "rcxc (as nqc): cannot write the error file " << o_.errors->file << ": " << *unwritten
                << "\n";
      return false;
    }
    return true;
  }

  int perform(const SourceStep& s) {
    // nqc reads a FILE named *.rcx (any case) as an image, as if -b were given.
    if (o_.binary || named_as_image(s.name)) return perform_binary(s.name);
    // Read with the cap every source has: /dev/zero or an endless pipe
    // ends with a message, not with the machine's memory.
    auto [name, read] = frontend::read_source(s.name);
    if (auto* problem = std::get_if<rcx::FileProblem>(&read)) {
      report_errors(*problem == rcx::FileProblem::TooLarge
                        ? fmt::format("# Error: {}\n", rcx::too_large_message(name, rcx::kSourceFile))
                        : fmt::format("# Error: cannot open file \"{}\"\n", s.name));
      return kNqcExitCompile;
    }
    std::string text = std::move(std::get<std::string>(read));
    // nqc prints a screen of the binary bytes; one line says what is wrong.
    if (std::string why = frontend::not_source_reason(name, text); !why.empty()) {
      report_errors("# Error: " + why + "\n");
      return kNqcExitCompile;
    }
    SourceManager sm;
    Diagnostics diags;
    ir::Log log;
    // rcxc compile's default level (-O2: never slower than nqc's code, never
    // larger); nqc has no levels. This mode was written when -Os was the
    // default and kept it, so BricxCC got code that trades time for bytes.
    auto out = backend::compile_source(name, std::move(text), o_.frontend, CompileRequest{}.level, sm, diags, log);
    bool reported = report_errors(render_nqc(diags, sm));
    if (!out || diags.has_errors() || !reported) return kNqcExitCompile;
    if (int code = write_outputs(s.name, *out, sm); code != kNqcExitOk) return code;
    if (o_.download) return download(out->image);
    return kNqcExitOk;
  }

  int perform_binary(const std::string& file) {
    auto image = rcx::read_image_file(file);
    if (auto* e = std::get_if<rcx::ImageError>(&image)) {
      report_errors(fmt::format("# Error: '{}' is not a valid RCX image: {}\n", file, e->message));
      return kNqcExitCompile;
    }
    const auto& read = std::get<rcx::Image>(image);
    // nqc lists an image it was given as it lists one it compiled.
    if (o_.listing) {
      auto style = o_.lasm_listing ? backend::ListingStyle::Lasm : backend::ListingStyle::Nqc;
      if (int code = write_listing(backend::nqc_listing(read, {}, style)); code != kNqcExitOk) return code;
    }
    if (o_.download) return download(read);
    return kNqcExitOk;
  }

  int write_listing(const std::string& text) {
    if (o_.listing->file.empty()) {
      std::cout << text;
    } else if (auto unwritten = savefile::write_file_atomically(o_.listing->file, text)) {
      std::cerr << "rcxc (as nqc): cannot write " << o_.listing->file << ": " << *unwritten << "\n";
      return kNqcExitCompile;
    }
    return kNqcExitOk;
  }

  int write_outputs(const std::string& source, const backend::Output& out, const SourceManager& sm) {
    std::optional<std::string> image_file = o_.output;
    // Without -O nqc writes FILE.rcx in the current folder, unless the call
    // asked for a listing or a download instead.
    if (!image_file && !o_.listing && !o_.download && source != "-")
      image_file = std::filesystem::path(source).filename().replace_extension(".rcx").string();
    for (const std::string* target : {image_file ? &*image_file : nullptr, o_.listing ? &o_.listing->file : nullptr}) {
      if (!target || target->empty()) continue;
      std::error_code ec;
      if (source != "-" && std::filesystem::equivalent(*target, source, ec) && !ec) {
        std::cerr << "rcxc (as nqc): refusing to write " << *target << ": it is the source file\n";
        return kNqcExitCompile;
      }
    }
    if (image_file) {
      auto bytes = rcx::write_image(out.image);
      if (auto unwritten = savefile::write_file_atomically(*image_file, std::string(bytes.begin(), bytes.end()))) {
        std::cerr << "rcxc (as nqc): cannot write " << *image_file << ": " << *unwritten << "\n";
        return kNqcExitCompile;
      }
    }
    if (o_.listing)
      return write_listing(backend::nqc_listing(out, o_.source_in_listing ? &sm : nullptr,
                                                o_.lasm_listing ? backend::ListingStyle::Lasm : backend::ListingStyle::Nqc));
    return kNqcExitOk;
  }

  // The tower, opened at the first step that needs it and kept for the rest.
  rcx::Link* link() {
    if (link_) return &*link_;
    auto opened = rcx::open_user_port(o_.port);
    if (auto* e = std::get_if<rcx::TransportError>(&opened)) {
      std::cerr << "rcxc (as nqc): " << e->message << "\n";
      return nullptr;
    }
    port_ = std::move(std::get<std::unique_ptr<rcx::Transport>>(opened));
    link_ = rcx::make_link(*port_, rcx::LinkOptions{});
    if (o_.verbose) link_->on_rejected = [](const std::string& why) { std::cerr << "rejected: " << why << "\n"; };
    return &*link_;
  }

  int download(const rcx::Image& image) {
    rcx::Link* l = link();
    if (!l) return kNqcExitLink;
    rcx::DownloadOptions options;
    options.program = program_;
    options.sound = !o_.quiet;
    auto result = rcx::download(*l, image, options, {});
    if (auto* e = std::get_if<rcx::DownloadError>(&result)) {
      std::cerr << "rcxc (as nqc): download failed: " << e->message << "\n";
      return e->kind == rcx::DownloadFailure::BadInput ? kNqcExitCompile : kNqcExitNoReply;
    }
    std::cerr << fmt::format("downloaded {} bytes to program {}\n", std::get<rcx::DownloadReport>(result).bytes,
                             program_);
    return kNqcExitOk;
  }

  // Text an action prints goes to standard output, or the -R file (opened
  // by run()). False, said on stderr, when the file could not take it.
  bool print_action_text(const std::string& text) {
    if (!text_file_) {
      std::cout << text;
      return true;
    }
    if (*text_file_ << text << std::flush) return true;
    std::cerr << text << "rcxc (as nqc): cannot write the output file " << *o_.text_output
              << " (-R); the text is above\n";
    return false;
  }

  // The link/remote words each nqc action stands for.
  std::variant<std::vector<std::vector<std::string>>, std::string> remote_words(const ActionStep& a) {
    const auto& w = a.words;
    if (a.name == "-run") return std::vector<std::vector<std::string>>{{"run"}};
    if (a.name == "-pgm") return std::vector<std::vector<std::string>>{{"program", w[0]}};
    if (a.name == "-datalog" || a.name == "-datalog_full") return std::vector<std::vector<std::string>>{{"datalog"}};
    // Set transmitter range (0x31): 0 near, 1 far.
    if (a.name == "-near") return std::vector<std::vector<std::string>>{{"raw", "31", "00"}};
    if (a.name == "-far") return std::vector<std::vector<std::string>>{{"raw", "31", "01"}};
    if (a.name == "-watch") return std::vector<std::vector<std::string>>{{"watch", w[0]}};
    if (a.name == "-firmware" || a.name == "-firmfast") return std::vector<std::vector<std::string>>{{"firmware", w[0]}};
    if (a.name == "-sleep") return std::vector<std::vector<std::string>>{{"sleep", w[0]}};
    if (a.name == "-msg") return std::vector<std::vector<std::string>>{{"message", w[0]}};
    if (a.name == "-clear") return std::vector<std::vector<std::string>>{{"clear"}};
    if (a.name == "-raw") {
      // nqc takes the packet as one word of hex digits.
      std::vector<std::string> words{"raw"};
      const std::string& hex = w[0];
      if (hex.size() % 2 != 0) return std::string("-raw wants an even number of hex digits, e.g. -raw 1002");
      for (std::size_t i = 0; i < hex.size(); i += 2) words.push_back(hex.substr(i, 2));
      return std::vector<std::vector<std::string>>{words};
    }
    return fmt::format("{} is not supported by rcxc yet (docs/nqc.md)", a.name);
  }

  int perform(const ActionStep& a) {
    if (a.name == "-help") {
      print_help();
      return kNqcExitOk;
    }
    if (a.name == "-api") {
      std::cout << stdlib::find("rcx.nqh").value_or("");
      return kNqcExitOk;
    }
    if (a.name == "-pgm") {
      if (!is_number(a.words[0])) return perform(UsageStep{"-pgm wants a program number 1..5"});
      program_ = std::atoi(a.words[0].c_str());
    }
    auto requests = remote_words(a);
    if (auto* why = std::get_if<std::string>(&requests)) return perform(UsageStep{*why});
    for (const auto& words : std::get<0>(requests)) {
      auto bad = rcx::check_remote(words);
      if (bad && bad->kind == rcx::RemoteFailure::Input) {
        // An unreadable firmware file counts as an unreadable input, as in nqc.
        std::cerr << "rcxc (as nqc): " << a.name << ": " << bad->message << "\n";
        return kNqcExitCompile;
      }
      if (bad) return perform(UsageStep{a.name + ": " + bad->message});
    }
    for (const auto& words : std::get<0>(requests)) {
      rcx::Link* l = link();
      if (!l) return kNqcExitLink;
      auto result = rcx::run_remote(*l, words);
      if (auto* e = std::get_if<rcx::RemoteError>(&result)) {
        std::cerr << "rcxc (as nqc): " << a.name << ": " << e->message << "\n";
        return e->kind == rcx::RemoteFailure::Input ? kNqcExitCompile : kNqcExitNoReply;
      }
      // nqc prints what it uploads (the datalog), not confirmations.
      bool printed = true;
      if (a.name == "-datalog" || a.name == "-datalog_full" || o_.verbose)
        printed = print_action_text(std::get<std::string>(result));
      if (!printed) return kNqcExitCompile;
    }
    return kNqcExitOk;
  }

  NqcOptions o_;
  int program_ = 1;
  std::unique_ptr<rcx::Transport> port_;
  std::optional<rcx::Link> link_;
  std::unique_ptr<std::ofstream> text_file_;
};

}  // namespace

bool started_as_nqc(const char* argv0) {
  if (!argv0) return false;
  std::string name = std::filesystem::path(argv0).filename().string();
  return name == "nqc" || name == "nqc.exe";
}

namespace {

// What to write instead of the word `a` when it is an nqc habit, or "".
std::string habit_instead(const std::string& a) {
  if (a.size() <= 2 || a[0] != '-' || a[1] == '-') return "";
  if (a[1] == 'E') return "errors always go to stderr here (-E prints the preprocessed source)";
  if (a[1] == 'L') return "write --listing=" + a.substr(2);
  if (a[1] == 'T') return "rcxc always compiles for the RCX: leave -T out";
  return "";
}

}  // namespace

std::vector<std::string> nqc_habit_hints(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (const std::string& a : args)
    if (std::string instead = habit_instead(a); !instead.empty())
      out.push_back(fmt::format("'{}' is nqc's option: {}; or run 'rcxc nqc ...' with nqc's options (docs/nqc.md)",
                                a, instead));
  return out;
}

bool left_of_nqc_habit(const std::string& unexpected, const std::vector<std::string>& args) {
  // CLI11 reads -Etemp.log as the flag -E and then "-temp.log", the rest of
  // the word as a word of its own: what is left of a habit is the habit or
  // a dash and a tail of it.
  const std::string& word = unexpected;
  for (const std::string& a : args) {
    if (habit_instead(a).empty()) continue;
    if (word == a) return true;
    if (word.size() >= 2 && word[0] == '-' && word.size() - 1 < a.size() - 1 &&
        a.ends_with(std::string_view(word).substr(1)))
      return true;
  }
  return false;
}

namespace {

// The first token at or after `at` (comments and blanks skipped), with its
// width when it is a name or number; at the end of the file (or when
// `at_end`: the parser found the end there), the place after its last
// character (the line after a last line end), where nqc reports it.
std::pair<SourceLoc, std::size_t> token_from(const SourceManager& sm, SourceLoc at, bool at_end) {
  const std::string& text = sm.text(at.file);
  // Lines end at LF, CR LF or a lone CR: at most one line per CR or LF.
  const auto lines = static_cast<std::uint32_t>(std::count(text.begin(), text.end(), '\n') +
                                                std::count(text.begin(), text.end(), '\r') + 1);
  bool in_comment = false;
  std::size_t i = at.column == 0 ? 0 : at.column - 1;
  for (std::uint32_t l = at.line; l <= lines && !at_end; ++l, i = 0) {
    std::string_view line = sm.line(at.file, l);
    while (i < line.size()) {
      if (in_comment) {
        std::size_t close = line.find("*/", i);
        if (close == std::string_view::npos) break;
        in_comment = false;
        i = close + 2;
      } else if (line[i] == ' ' || line[i] == '\t' || line[i] == '\f' || line[i] == '\v') {
        ++i;
      } else if (line.substr(i, 2) == "//") {
        break;
      } else if (line.substr(i, 2) == "/*") {
        in_comment = true;
        i += 2;
      } else {
        std::size_t width = 0;
        while (i + width < line.size() && (std::isalnum(static_cast<unsigned char>(line[i + width])) || line[i + width] == '_'))
          ++width;
        return std::pair{SourceLoc{at.file, l, static_cast<std::uint32_t>(i + 1), 0}, std::max<std::size_t>(width, 1)};
      }
    }
  }
  std::uint32_t last = 1;
  for (std::size_t c = 0; c < text.size(); ++c)
    if (text[c] == '\n' || (text[c] == '\r' && (c + 1 == text.size() || text[c + 1] != '\n'))) ++last;
  return std::pair{SourceLoc{at.file, last, static_cast<std::uint32_t>(sm.line(at.file, last).size() + 1), 0},
                   std::size_t{1}};
}

}  // namespace

std::string render_nqc(const Diagnostics& diags, const SourceManager& sm) {
  std::string out;
  for (const Diagnostic* d : in_source_order(diags, sm)) {
    if (d->severity == Severity::Note) continue;
    out += fmt::format("# {}: {}\n", d->severity == Severity::Error ? "Error" : "Warning", d->message);
    SourceLoc at = user_location(d->span.begin, sm);
    if (at.valid() && at.file < sm.size()) {
      std::size_t width = 1;
      const SourceLoc& end = d->span.end;
      if (at.expansion == 0 && d->span.begin.expansion == 0 && end.file == at.file && end.line == at.line &&
          end.column > at.column)
        width = end.column - at.column;
      // rcxc puts a missing ';' just after what it should end; nqc's parser
      // reports it at the token it found instead, often on the next line,
      // and that is the line a tool reading nqc's messages expects. The
      // message ("expected ';' before 'Wait'") names that token, or the end
      // of the file.
      if (d->message.rfind("expected ';'", 0) == 0 && at == d->span.begin && at.expansion == 0)
        std::tie(at, width) = token_from(sm, at, d->message.ends_with("before end of file"));
      // BricxCC finds the line by searching this line for "line N".
      out += fmt::format("File \"{}\" ; line {}\n", file_label(at.file, sm), at.line);
      QuotedLine quoted = quote_line(sm.line(at.file, at.line), at.column == 0 ? 0 : at.column - 1, width);
      out += fmt::format("# {}\n# {}{}\n", quoted.text, quoted.lead_in, std::string(quoted.width, '^'));
    }
    out += "#----------------------------------------------------------\n";
  }
  std::size_t errors = diags.error_count();
  if (errors != 0) out += fmt::format("# {} error{} during compilation\n", errors, errors == 1 ? "" : "s");
  return out;
}

int run_nqc_mode(const std::vector<std::string>& args) {
  try {
    return Session(parse_command_line(with_environment_options(args))).run();
  } catch (const std::exception& e) {
    // A bug or an exhausted machine; say so rather than abort.
    std::cerr << "rcxc (as nqc): internal error: " << e.what() << "\n";
    return kNqcExitCompile;
  }
}

}  // namespace rcxc::cli
