// sva: one CLI with subcommands. Every error a user can cause ends here as a
// one-line message on stderr and a non-zero exit code.
#include <sva/base/interrupt.hpp>
#include <sva/base/progress.hpp>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "args.hpp"

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const std::vector<std::string>&);
};

const Command kCommands[] = {
    {"demo", "the main job: simulate the default scene, train, evaluate, print the table and draw the figure",
     sva::cli::cmd_demo},
    {"simulate", "simulate tactile readings of a scene's objects with the Embree simulator", sva::cli::cmd_simulate},
    {"inspect", "summarise a dataset or map file", sva::cli::cmd_inspect},
    {"export", "write a dataset as CSV and PLY (contact points with normals), or as a session recording",
     sva::cli::cmd_export},
    {"train", "build the SVA pair map (appearance classes + surface-patch pairs) from training readings",
     sva::cli::cmd_train},
    {"eval", "run recognition trials on test readings and report accuracy and pose errors", sva::cli::cmd_eval},
    {"recognize", "recognise a batch of sessions of readings", sva::cli::cmd_recognize},
    {"bench", "measure votes per second and time per update", sva::cli::cmd_bench},
    {"record", "record a real tactile sensor and the arm's poses into a session file", sva::cli::cmd_record},
    {"live", "recognise while touching with a real tactile sensor and the arm's poses", sva::cli::cmd_live},
    {"calibrate", "record a tactile array's zero counts (tare) into a calibration file", sva::cli::cmd_calibrate},
    {"replay", "play a session recording: the readings it forms and, with a map, the estimates", sva::cli::cmd_replay},
    {"view", "write one session as an HTML page: a 3-D view of the touches and hypotheses, reading by reading",
     sva::cli::cmd_view},
};

void usage() {
  std::printf(
      "usage: sva <command> [options]\n\nTactile object recognition and localization by spatially-varying "
      "appearance.\n\ncommands:\n");
  for (const auto& c : kCommands) std::printf("  %-10s %s\n", c.name, c.summary);
  std::printf("\nRun 'sva <command> --help' for a command's options. Global: --quiet (no progress), --version.\n");
}

}  // namespace

int main(int argc, char** argv) {
  sva::util::install_interrupt_handler();
  std::vector<std::string> args(argv + 1, argv + argc);
  std::erase_if(args, [](const std::string& a) {
    if (a == "--quiet" || a == "-q") {
      sva::util::Progress::set_quiet(true);
      return true;
    }
    return false;
  });
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    usage();
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::printf("sva %s\n", SVA_VERSION);
    return 0;
  }
  for (const auto& c : kCommands) {
    if (args[0] != c.name) continue;
    try {
      return c.run(std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const sva::Interrupted&) {
      std::fprintf(stderr, "\nsva %s: interrupted; no partial output was kept\n", c.name);
      return 130;
    } catch (const sva::Error& e) {
      // Argument errors already name the command; say it once.
      std::string message = e.what();
      const std::string prefix = std::string("sva ") + c.name + ": ";
      if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
      std::fprintf(stderr, "sva %s: error: %s\n", c.name, message.c_str());
      return 1;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "sva %s: error: out of memory\n", c.name);
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sva %s: internal error: %s\n", c.name, e.what());
      return 3;
    }
  }
  std::fprintf(stderr, "sva: unknown command \"%s\"\n\n", args[0].c_str());
  usage();
  return 2;
}
