#include "crowd/bake/job_process.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "build_inputs_json.h"
#include "crowd/bake/content_cache.h"
#include "crowd/formats/error.h"

extern char **environ;

namespace crowd {

using nlohmann::json;

namespace {

std::atomic<bool> interruptFlag{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

void onInterrupt(int signal) {
  interruptFlag = true;
  struct sigaction again {};
  again.sa_handler = SIG_DFL; // a second interrupt ends the process
  sigaction(signal, &again, nullptr);
}

// The child's last error line without its "crowdbake: error: " (what printFailure writes), or
// its last line.
std::string lastError(const std::string &stderrText) {
  std::string last, error;
  size_t start = 0;
  while (start < stderrText.size()) {
    size_t end = stderrText.find('\n', start);
    if (end == std::string::npos)
      end = stderrText.size();
    const std::string line = stderrText.substr(start, end - start);
    if (!line.empty())
      last = line;
    if (line.rfind("crowdbake: error: ", 0) == 0)
      error = line.substr(18);
    start = end + 1;
  }
  return error.empty() ? last : error;
}

// Runs `argv` with its stderr into a pipe; returns the pid and the pipe's reading end.
std::pair<pid_t, int> spawn(const std::string &executable, const std::vector<std::string> &args) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Error(std::string("cannot create a pipe for a job: ") + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  std::vector<char *> argv;
  argv.push_back(const_cast<char *>(executable.c_str()));
  for (const auto &a : args)
    argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    throw Error("cannot start " + executable + " for a job: " + std::strerror(rc));
  }
  return {pid, fds[0]};
}

} // namespace

void catchInterrupts() {
  struct sigaction on {};
  on.sa_handler = onInterrupt;
  sigemptyset(&on.sa_mask);
  sigaction(SIGINT, &on, nullptr);
  sigaction(SIGTERM, &on, nullptr);
}

bool interruptRequested() { return interruptFlag.load(); }

std::string JobSpec::text() const {
  json j{{"library", library},
         {"entry", entry},
         {"job", job},
         {"key", key},
         {"cache", cache},
         {"threads", threads},
         {"max_seconds", limits.maxSeconds},
         {"max_memory_mib", limits.maxMemoryMiB},
         {"parent", parent}};
  writeBuildInputs(j, files, scene);
  return j.dump();
}

JobSpec JobSpec::parse(const std::string &text) {
  try {
    const json j = json::parse(text);
    JobSpec s;
    s.library = j.at("library");
    s.entry = j.at("entry");
    s.job = j.at("job");
    s.key = j.at("key");
    s.cache = j.at("cache");
    s.threads = j.at("threads");
    readBuildInputs(j, s.files, s.scene);
    s.limits.maxSeconds = j.at("max_seconds");
    s.limits.maxMemoryMiB = j.at("max_memory_mib");
    s.parent = j.at("parent");
    s.limits.validate();
    return s;
  } catch (const Error &) {
    throw;
  } catch (const std::exception &e) {
    throw Error(std::string("not a job spec (crowdbake build writes them): ") + e.what());
  }
}

JobProcessOutcome runJobProcess(const std::string &executable, const JobSpec &spec) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto [pid, pipe] = spawn(executable, {"build-job", spec.text()});
  std::string text; // the child's stderr (its tail)
  bool timedOut = false, stopped = false;
  for (;;) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    int waitMs = 200; // how often an interrupt is looked for
    if (spec.limits.maxSeconds > 0) {
      const double left = spec.limits.maxSeconds - elapsed;
      if (left <= 0 && !timedOut) {
        ::kill(pid, SIGKILL);
        timedOut = true;
      }
      if (!timedOut)
        waitMs = std::min(waitMs, int(left * 1000) + 1);
    }
    if (interruptRequested() && !stopped) {
      ::kill(pid, SIGTERM);
      stopped = true;
    }
    pollfd p{pipe, POLLIN, 0};
    const int n = ::poll(&p, 1, waitMs);
    if (n <= 0)
      continue; // a timeout, or a signal (EINTR)
    char buffer[4096];
    const ssize_t got = ::read(pipe, buffer, sizeof buffer);
    if (got == 0 || (got < 0 && errno != EINTR))
      break; // the child closed its stderr: it ended
    if (got > 0)
      text.append(buffer, size_t(got));
    if (text.size() > (1 << 16))
      text.erase(0, text.size() - (1 << 14));
  }
  ::close(pipe);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  JobProcessOutcome o;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    o.ok = true;
    return o;
  }
  // A child ended by a signal may leave temporary files beside its entry.
  ContentCache(spec.cache).removeTemporaries(spec.key, pid);
  const int signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  char line[160];
  if (stopped || (interruptRequested() && (signal == SIGINT || signal == SIGTERM))) {
    o.interrupted = true;
    o.error = "interrupted";
  } else if (timedOut) {
    std::snprintf(line, sizeof line, "ran %.1f s, over --job-max-seconds %g s: killed", seconds,
                  spec.limits.maxSeconds);
    o.error = line;
  } else if (signal) {
    o.killedFromOutside = signal == SIGKILL || signal == SIGTERM || signal == SIGINT;
    std::snprintf(line, sizeof line, "%s by signal %d (%s)",
                  o.killedFromOutside ? "killed" : "crashed", signal, strsignal(signal));
    o.error = line;
  } else {
    o.error = lastError(text);
    if (o.error.empty())
      o.error = "exited with code " + std::to_string(WEXITSTATUS(status)) + " and no error line";
  }
  return o;
}

} // namespace crowd
