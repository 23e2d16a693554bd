// pkm: the command-line layer. Parses arguments, wires modules, prints, and exits.
#include <CLI/CLI.hpp>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/linuxcnc/ini_file.hpp"
#include "version.hpp"

namespace {

// SIGINT, SIGTERM, SIGHUP: remove the temporaries of unfinished outputs, then die of the same
// signal (SA_RESETHAND restored the default action), so the caller sees how the run ended.
extern "C" void remove_temporaries_and_die(int signal_number) {
  pkm::files::remove_open_temporaries();
  std::raise(signal_number);
}

void remove_temporaries_on_signals() {
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_die;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    // A signal ignored when pkm started stays ignored: nohup's SIGHUP, a background job's SIGINT.
    struct sigaction inherited {};
    sigaction(signal_number, nullptr, &inherited);
    if (inherited.sa_handler != SIG_IGN) sigaction(signal_number, &action, nullptr);
  }
}

void warn_of_stale_temporary(const pkm::files::StaleTemporary& stale) {
  const std::string size = stale.size_bytes < 1000000
                               ? std::to_string(stale.size_bytes) + " bytes"
                               : std::to_string(stale.size_bytes / 1000000) + " MB";
  if (stale.failure.empty()) {
    std::fprintf(stderr,
                 "pkm: warning: removed %s (%s), a temporary file left by an interrupted run "
                 "(%s)\n",
                 stale.path.c_str(), size.c_str(), stale.why.c_str());
  } else {
    std::fprintf(stderr,
                 "pkm: warning: cannot remove %s (%s), a temporary file left by an interrupted "
                 "run (%s): %s\n",
                 stale.path.c_str(), size.c_str(), stale.why.c_str(), stale.failure.c_str());
  }
}

// Whether everything written to the standard output reached it: a full disk or a closed pipe
// shows only when the buffers are flushed, and a command whose output did not arrive has failed
// (`pkm import linuxcnc X.ini > m.toml` on a full disk once exited 0 with an empty file).
bool standard_output_written() {
  // stdio keeps only a flag once a write failed; errno still holds the write's reason unless a
  // later call failed for another: the reason is named when it is one a write gives.
  const int earlier = errno;
  errno = 0;
  std::fflush(stdout);
  std::cout.flush();  // synchronised with stdio: flushes stdout again
  const int reason = errno != 0 ? errno : earlier;
  if (std::cout.good() && std::ferror(stdout) == 0) return true;
  const bool write_reason =
      reason == ENOSPC || reason == EPIPE || reason == EIO || reason == EDQUOT || reason == EFBIG;
  std::fprintf(stderr,
               "pkm: error: writing the standard output failed (%s): what it holds is "
               "incomplete\n",
               write_reason ? std::strerror(reason) : "a write error");
  return false;
}

std::string version_text() {
  std::string text = std::string("pkm ") + pkm::app::kVersion;
  if (pkm::app::kGitDescribe[0] != '\0')
    text += std::string(" (git ") + pkm::app::kGitDescribe + ")";
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  remove_temporaries_on_signals();
  pkm::files::on_stale_temporary(warn_of_stale_temporary);
  CLI::App app{"pkmkit: drive parallel-kinematic machines from Cartesian G-code", "pkm"};
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);
  pkm::app::register_kinematics_commands(app);
  pkm::app::register_gcode_commands(app);
  pkm::app::register_plan_commands(app);
  pkm::app::register_post_commands(app);
  pkm::app::register_verify_commands(app);
  pkm::app::register_view_commands(app);
  pkm::app::register_calibrate_commands(app);
  pkm::app::register_linuxcnc_commands(app);
  pkm::app::register_linuxcnc_import_commands(app);
  pkm::app::register_firmware_commands(app);
  pkm::app::register_home_commands(app);
  pkm::app::register_workspace_commands(app);
  pkm::app::register_stream_commands(app);
  errno = 0;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version end parsing as "errors" of status 0; CLI11's own statuses (105 for a
    // refused value) mean nothing to a user, so a refusal is 2 with the prefix of every error.
    if (error.get_exit_code() == 0) return app.exit(error);
    std::fprintf(stderr, "pkm: error: %s\nRun with --help for more information.\n", error.what());
    return 2;
  } catch (const pkm::machine::MachineFileError& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  } catch (const pkm::linuxcnc::ConfigError& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  } catch (const pkm::app::CommandError& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  }
  return standard_output_written() ? 0 : 1;
}
