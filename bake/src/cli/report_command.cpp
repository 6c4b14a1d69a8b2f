// crowdbake report: build and bake reports as one HTML page (crowd/bake/report_page.h).
#include <filesystem>

#include "commands.h"
#include "crowd/bake/input_files.h"
#include "crowd/bake/report_page.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/json_checker.h"

namespace crowd::cli {

namespace {

const char *const kReportHelp =
    R"(Turns build reports (crowdbake build's OUTDIR/build.report.json, or
the --report of a single-character build) and bake reports (any bake's --report) into one HTML
page a person reads: per build and character, every job's time, size and accuracy, and the
charts: the animation's error against bytes for every frame rate and precision tried (with the
error budget), LOD error against triangles, impostor accuracy against memory, the cloth loop's
pass-1 seam search and each candidate's pass-1 and pass-2 scores. One file, SVG inline, no
scripts, no network: open it in any browser or attach it to a CI run.)";

ReportSource readReport(const std::string &input) {
  std::filesystem::path path = input;
  if (std::filesystem::is_directory(path))
    path /= "build.report.json";
  if (!std::filesystem::exists(path))
    throw Error(path.string() + ": cannot open" +
                (path.filename() == "build.report.json" ? " (not a build's output folder?)" : ""));
  const std::string name = path.string(), text = readInputText(name, InputPolicy{});
  return {name, runtime::JsonChecker(text, name).parse()};
}

} // namespace

int cmdReport(int argc, char **argv) {
  std::vector<std::string> inputs;
  std::string output;
  CLI::App app(kReportHelp, "crowdbake report");
  example(app, "crowdbake build library.json -o lib --report build.json && "
               "crowdbake report lib -o report.html");
  app.add_option("INPUTS", inputs, "build reports, build output folders or bake reports")
      ->required();
  app.add_option("-o,--output", output, "the HTML page to write (atomically)")->required();
  if (!parseArgs(app, argc, argv))
    return 0;
  std::vector<ReportSource> sources;
  for (const auto &input : inputs)
    sources.push_back(readReport(input));
  const std::string page = reportPage(sources);
  pack::writeFileAtomic(output, {reinterpret_cast<const uint8_t *>(page.data()), page.size()});
  return 0;
}

} // namespace crowd::cli
