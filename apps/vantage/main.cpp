// vantage: where to put depth cameras so that together they see the most of the targets.
// Exit codes: 0 success, 2 bad input (file:line: what is wrong), 1 internal failure.
#include <fmt/format.h>
#include <malloc.h>
#include <fmt/ranges.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <limits>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "vantage/interrupt.hpp"
#include "vantage/words.hpp"

namespace {

// The long and short names of the options of `app` (a command) and of the top level.
std::vector<std::string> OptionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* level = &app; level != nullptr; level = level->get_parent())
    for (const CLI::Option* option : level->get_options()) {
      for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
      for (const std::string& name : option->get_snames()) names.push_back("-" + name);
    }
  return names;
}

// A whole number in decimal that CLI11 could not convert is out of the option's range (was: "not a
// whole number" for -n 2147483648). CLI11's integer options are 32 or 64 bits wide, so one that
// fits 64 bits failed on 32 bits: then the limit is known; else only the end is.
std::optional<std::string> OutOfRange(const std::string& value, bool is_unsigned) {
  std::string_view digits(value);
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  const bool negative = !digits.empty() && digits.front() == '-';
  const std::string_view magnitude = negative ? digits.substr(1) : digits;
  if (magnitude.empty() || magnitude.find_first_not_of("0123456789") != std::string_view::npos)
    return std::nullopt;
  if (negative && is_unsigned) return "negative — give a whole number >= 0";
  const char* end = digits.data() + digits.size();
  uint64_t as_unsigned = 0;
  int64_t as_signed = 0;
  const bool fits_64_bits =
      is_unsigned ? std::from_chars(digits.data(), end, as_unsigned).ec == std::errc()
                  : std::from_chars(digits.data(), end, as_signed).ec == std::errc();
  if (!fits_64_bits)
    return fmt::format("too {} for a whole number of 64 bits", negative ? "small" : "large");
  const bool fits_32_bits =
      is_unsigned ? as_unsigned <= std::numeric_limits<uint32_t>::max()
                  : as_signed >= std::numeric_limits<int32_t>::min() &&
                        as_signed <= std::numeric_limits<int32_t>::max();
  if (fits_32_bits) return std::nullopt;  // not a matter of range
  if (negative) return fmt::format("too small — give at least {}", std::numeric_limits<int32_t>::min());
  if (is_unsigned)
    return fmt::format("too large — give at most {}", std::numeric_limits<uint32_t>::max());
  return fmt::format("too large — give at most {}", std::numeric_limits<int32_t>::max());
}

// What an option takes, in words, from CLI11's type name ("INT", "UINT", "FLOAT", "BOOL", "TEXT").
struct ValueWords {
  std::string kind = "a value of another kind";
  bool whole_number = false;
  bool is_unsigned = false;
};
ValueWords WordsFor(const CLI::Option* option) {
  ValueWords words;
  if (option == nullptr) return words;
  const std::string type = option->get_type_name();
  words.whole_number = type.find("INT") != std::string::npos;
  words.is_unsigned = type.find("UINT") != std::string::npos;
  if (words.is_unsigned)
    words.kind = "a whole number >= 0";
  else if (words.whole_number)
    words.kind = "a whole number";
  else if (type.find("FLOAT") != std::string::npos)
    words.kind = "a number";
  else if (type.find("BOOL") != std::string::npos)
    words.kind = "true or false";
  else
    words.kind = "a text";
  return words;
}

// The command the words were given to (or the top level), its option `name`, and where to look.
const CLI::App& ChosenCommand(const CLI::App& app) {
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  return chosen.empty() ? app : *chosen.front();
}
const CLI::Option* FindOption(const CLI::App& app, const std::string& name) {
  const CLI::Option* option = ChosenCommand(app).get_option_no_throw(name);
  return option != nullptr ? option : app.get_option_no_throw(name);
}
std::string HelpFor(const CLI::App& app) {
  const CLI::App& command = ChosenCommand(app);
  return &command == &app ? "`vantage --help`" : fmt::format("`vantage help {}`", command.get_name());
}

// CLI11 says "Could not convert: --k = x" for a value of the wrong type, which names neither what
// the option takes nor where to look: name the option, the value and the kind it wants.
std::optional<std::string> ConversionMessage(const CLI::App& app, const CLI::ParseError& error) {
  const std::string what = error.what();
  const std::string prefix = "Could not convert: ";
  const size_t equals = what.find(" = ");
  if (what.rfind(prefix, 0) != 0 || equals == std::string::npos) return std::nullopt;
  const std::string name = what.substr(prefix.size(), equals - prefix.size());
  const std::string value = what.substr(equals + 3);
  const CLI::Option* option = FindOption(app, name);
  // "-n,--sensors": the one typed may be the short name
  const std::string names = option != nullptr ? option->get_name(false, true) : name;
  const ValueWords words = WordsFor(option);
  if (words.whole_number) {
    if (auto range = OutOfRange(value, words.is_unsigned))
      return fmt::format("{}: '{}' is {}", names, value, *range);
  }
  return fmt::format("{}: '{}' is not {} — {} says what it takes", names, value, words.kind,
                     HelpFor(app));
}

// Every other refusal of CLI11 in vantage's voice (was: CLI11's own line, e.g. "scene is
// required", "--sensors: 1 required INT missing", then "Run with --help for more information.",
// without the `[error]` of every other refusal): a missing command, argument or value is named
// with what it takes; a validator's message (already "--option: what is wrong — what to give") is
// kept as it is.
std::string UsageMessage(const CLI::App& app, const std::vector<std::string>& commands,
                         const CLI::ParseError& error) {
  const std::string what = error.what();
  const std::string help = HelpFor(app);
  const std::string name = error.get_name();
  if (name == "ValidationError") return what;
  if (name == "RequiredError") {
    if (&ChosenCommand(app) == &app)
      return fmt::format("no command given — use one of {} (`vantage --help` describes them)",
                         fmt::join(commands, ", "));
    const std::string suffix = " is required";
    if (what.size() > suffix.size() && what.ends_with(suffix)) {
      const std::string missing = what.substr(0, what.size() - suffix.size());
      if (const CLI::Option* option = FindOption(app, missing); option && option->get_positional())
        return fmt::format("`vantage {}` needs its {} argument ({}) — {} shows what it takes",
                           ChosenCommand(app).get_name(), missing, option->get_description(), help);
    }
  }
  if (name == "ArgumentMismatch") {
    // "--sensors: 1 required INT missing": the option was given without its value.
    const std::string option_name = what.substr(0, what.find(':'));
    if (const CLI::Option* option = FindOption(app, option_name)) {
      const int count = option->get_items_expected_min();
      const std::string kind = WordsFor(option).kind;
      const bool named = kind != "a text";  // a path or a name: "a value" says it
      const std::string values =
          count > 1 ? fmt::format("{} values{}", count, named ? fmt::format(" ({} each)", kind) : "")
                    : fmt::format("a value{}", named ? fmt::format(" ({})", kind) : "");
      return fmt::format("{}: needs {} after it — {} says what it takes",
                         option->get_name(false, true), values, help);
    }
  }
  return fmt::format("{} — {} says what it takes", what, help);
}

// What CLI11 says of a word it does not know ("The following arguments were not expected: greedy
// --methd", or "unknown command '2'" for `--threds 2 optimize`) names neither the word nor the fix:
// name the first unknown word of the command line — an option with the closest known one, a
// command, or an argument too many. Empty when the error is of another kind.
std::optional<std::string> UnknownWordMessage(const CLI::App& app,
                                              const std::vector<std::string>& commands,
                                              const std::vector<std::string>& command_line) {
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  const CLI::App& command = chosen.empty() ? app : *chosen.front();
  std::vector<std::string> rest = command.remaining();
  if (!chosen.empty()) {
    const std::vector<std::string> top = app.remaining();
    rest.insert(rest.end(), top.begin(), top.end());
  }
  // CLI11 lists them in no useful order: the first on the command line is the one to name.
  const auto first = std::find_if(command_line.begin(), command_line.end(), [&](const std::string& a) {
    return std::find(rest.begin(), rest.end(), a) != rest.end();
  });
  if (first == command_line.end()) return std::nullopt;
  const std::string& word = *first;
  const std::string where = chosen.empty() ? "" : fmt::format(" of `{}`", command.get_name());
  const std::string help = HelpFor(app);
  if (word.size() >= 2 && word[0] == '-') {
    const std::string flag = word.substr(0, word.find('='));
    const std::vector<std::string> names = OptionNames(command);
    if (const std::string* best = vantage::ClosestWord(flag, names))
      return fmt::format("unknown option '{}'{} — did you mean '{}'? ({} lists them)", flag, where,
                         *best, help);
    return fmt::format("unknown option '{}'{} — {} lists the options", flag, where, help);
  }
  if (chosen.empty()) {
    const std::string* best = vantage::ClosestWord(word, commands);
    return fmt::format("unknown command '{}' — {}use one of {} (`vantage --help` describes them)",
                       word, best ? fmt::format("did you mean '{}'? ", *best) : "",
                       fmt::join(commands, ", "));
  }
  return fmt::format("unexpected argument '{}'{} — {} shows what it takes", word, where, help);
}

int Run(int argc, char** argv, spdlog::logger* logger, const vantage::MpiJob* job) {
  CLI::App app{"vantage — choose where to put depth cameras to see the most of the targets.\n"
               "Run `vantage help COMMAND` for the options of a command.",
               "vantage"};
  app.require_subcommand(1);
  app.set_version_flag("--version", vantage::Version());
  int threads = 0;
  bool quiet = false;
  int verbosity = 0;
  app.add_option("--threads", threads, "worker threads (default: all cores)")
      ->check(vantage::cli::NumberFrom(0, 4096, vantage::cli::ValueKind::kWholeNumber))
      ->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "only errors on stderr");
  app.add_flag("-v,--verbose", verbosity, "more log detail (repeatable)");
  app.fallthrough();
  // Applied once parsing is complete, before the command's callback runs (STYLE.md: main
  // applies --threads once).
  std::unique_ptr<tbb::global_control> thread_limit;
  app.parse_complete_callback([&] {
    // Under mpirun only optimize and observe spread their work; the others run in one process.
    for (const CLI::App* command : app.get_subcommands()) {
      const std::string& name = command->get_name();
      if (job && job->size() > 1 && name != "optimize" && name != "observe")
        throw vantage::InputError(fmt::format(
            "mpirun: `vantage {}` runs in one process — run it without mpirun (only optimize and "
            "observe spread over ranks, docs/distributed.md)",
            name));
    }
    if (quiet) logger->set_level(spdlog::level::err);
    if (verbosity > 0) logger->set_level(spdlog::level::debug);
    if (threads > 0)
      thread_limit = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  });

  vantage::cli::SetupOptimize(&app);
  vantage::cli::SetupObserve(&app);
  vantage::cli::SetupSelect(&app);
  vantage::cli::SetupEvaluate(&app);
  vantage::cli::SetupSensors(&app);
  vantage::cli::SetupRender(&app);
  vantage::cli::SetupMerge(&app);
  auto* help = app.add_subcommand("help", "show the options of a command");
  std::string help_topic;
  help->add_option("command", help_topic, "command name");
  std::vector<std::string> commands;
  for (CLI::App* command : app.get_subcommands({})) {
    commands.push_back(command->get_name());
    // The unsigned options: CLI11 reads -1 as 2^64 - 1 and clamps 2^64 (issue 15).
    for (const char* name : {"--seed", "--calibration-overlap"}) {
      if (CLI::Option* option = command->get_option_no_throw(name))
        option->check(vantage::cli::WholeNumberValidator());
    }
  }
  // Every value: not empty, a number without spaces around it, and whole numbers in decimal. For
  // a number a transform (CLI11 runs it first, so the range checks see the trimmed value); for
  // text a check, run after the option's own (e.g. --out's "the path is empty").
  std::vector<CLI::App*> every_command = app.get_subcommands({});
  every_command.push_back(&app);
  for (CLI::App* command : every_command) {
    for (CLI::Option* option : command->get_options()) {
      if (option->get_type_size_min() == 0) continue;  // a flag: no value
      const std::string type = option->get_type_name();
      using vantage::cli::ValueKind;
      const ValueKind kind = type.find("INT") != std::string::npos     ? ValueKind::kWholeNumber
                             : type.find("FLOAT") != std::string::npos ? ValueKind::kNumber
                                                                       : ValueKind::kText;
      if (kind == ValueKind::kText)
        option->check(vantage::cli::PlainValueValidator(kind));  // after the option's own words
      else
        option->transform(vantage::cli::PlainValueValidator(kind));
    }
  }

  // `vantage help X` becomes `X --help` (CLI11 has no help command).
  std::vector<std::string> args(argv + 1, argv + argc);
  // An unknown X is parsed alone, so that it is refused as a command with its suggestion (was:
  // the general help, exit 0).
  if (!args.empty() && args[0] == "help") {
    const bool known = args.size() >= 2 &&
                       std::find(commands.begin(), commands.end(), args[1]) != commands.end();
    args = args.size() < 2 ? std::vector<std::string>{"--help"}
           : known         ? std::vector<std::string>{args[1], "--help"}
                           : std::vector<std::string>{args[1]};
  }
  std::reverse(args.begin(), args.end());
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() != 0) {
      std::vector<std::string> command_line(argv + 1, argv + argc);
      // A value not converted comes first: `-n --out x` takes "--out" as -n's value, and x is
      // then a word too many only because of it.
      if (auto message = ConversionMessage(app, e)) throw vantage::InputError(*message);
      if (auto message = UnknownWordMessage(app, commands, command_line))
        throw vantage::InputError(*message);
      throw vantage::InputError(UsageMessage(app, commands, e));
    }
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  return 0;
}

// A full disk or a closed pipe on stdout (`vantage sensors > /dev/full`) is neither a success
// nor an internal error: stdout is flushed before exiting and its failure reported.
bool StdoutFailed(spdlog::logger* logger) {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return false;
  logger->error("cannot write to standard output ({}) — check where it goes (a full disk?)",
                std::strerror(errno));
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // Memory freed by one stage is reused by the next rather than handed back to the system and
  // faulted in again (issue 47: page faults were a fifth of a run's time on these machines; the
  // occlusion world's 11 k faults a run fall to 7 k). glibc mmaps each block above 128 kB and
  // gives it back when freed; here only blocks from 32 MiB (the most mallopt allows) are, and the
  // heap's free top is kept up to 1 GiB. The process is short-lived; the library leaves malloc be.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  auto logger = spdlog::stderr_color_mt("vantage");
  logger->set_pattern("[%l] %v");
  spdlog::set_default_logger(logger);
  int code = 0;
  std::string message;  // the failure to report
  bool internal = false;
  std::unique_ptr<vantage::MpiJob> job;
  // Ctrl-C and SIGTERM stop the running stage within a fraction of a second (it throws
  // Interrupted); nothing is written after that, so the earlier outputs stay as they were.
  // (mpirun forwards the signal to every rank, and each stops alike.)
  const vantage::InterruptOnSignals interrupts;
  try {
    job = vantage::MpiJob::Start(&argc, &argv);  // under mpirun: MPI_Init
    code = Run(argc, argv, logger.get(), job.get());
  } catch (const vantage::Interrupted& e) {
    logger->error("{} — stopped; nothing was written, earlier outputs are as they were", e.what());
    return 128 + (e.signal() != 0 ? e.signal() : SIGINT);  // as a shell reports a signal
  } catch (const vantage::JobStopped& e) {
    code = e.code();  // the ranks agreed to stop; this rank prints its part, if any
    if (*e.what()) logger->error("{}", e.what());
    return code;
  } catch (const vantage::InputError& e) {
    code = 2;
    message = e.what();
  } catch (const std::exception& e) {
    code = 1;
    // fmt::print throws when a write fails; StdoutFailed then says so.
    internal = !StdoutFailed(logger.get());
    if (internal) message = fmt::format("internal error: {}", e.what());
  }
  if (code != 1 && message.empty() && StdoutFailed(logger.get())) code = 1;
  // An MPI job ends together: every rank's code, each failure reported once, naming its rank.
  if (job && !job->stopped()) code = job->Finish(code, message, &message);
  if (!message.empty()) {
    if (internal) {
      logger->critical("{}", message);
    } else {
      logger->error("{}", message);
    }
  }
  return code;
}
