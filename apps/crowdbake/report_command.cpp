// crowdbake report: build and bake reports as one HTML page (crowd/bake/report_page.h).
#include <filesystem>

#include "commands.h"
#include "crowd/bake/input_files.h"
#include "crowd/bake/report_page.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"
#include "crowd/support/json_checker.h"

namespace crowd::cli {

namespace {

const char *const kReportHelp =
    R"(Turns build reports (crowdbake build's OUTDIR/build.report.json, or
the --report of a single-character build) and bake reports (any bake's --report) into one HTML
page a person reads: per build and character, every job's time, size and accuracy, and the
charts: the animation's error against bytes for every frame rate and precision tried (with the
error budget), LOD error against triangles, impostor accuracy against memory, the cloth loop's
pass-1 seam search and each candidate's pass-1 and pass-2 scores. One file, SVG inline, no
scripts, no network: open it in any browser or attach it to a CI run. A build of more than 20
characters gets a summary table on the page, the failed first, each name linking to its own
page in the folder beside it (OUTPUT's name with .characters), so that a farm's report of a
thousand characters opens at once.)";

ReportSource readReport(const std::string &input) {
  std::filesystem::path path = input;
  if (std::filesystem::is_directory(path))
    path /= "build.report.json";
  if (!std::filesystem::exists(path))
    throw Error(path.string() + ": cannot open" +
                (path.filename() == "build.report.json" ? " (not a build's output folder?)" : ""));
  const std::string name = path.string(), text = readInputText(name, InputPolicy{});
  return {name, support::JsonChecker(text, name).parse()};
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
  namespace fs = std::filesystem;
  // Beside the page: OUTPUT's name with ".characters" for the pages of a large build's characters.
  const fs::path details = fs::path(output).stem().string() + ".characters";
  const ReportPages pages = reportPages(sources, details.string());
  auto write = [](const fs::path &path, const std::string &html) {
    pack::writeFileAtomic(path.string(),
                          {reinterpret_cast<const uint8_t *>(html.data()), html.size()});
  };
  if (!pages.characterPages.empty()) {
    const fs::path folder = fs::path(output).parent_path() / details;
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec)
      throw Error(folder.string() +
                  ": cannot create the characters' pages folder: " + ec.message());
    for (const auto &[file, html] : pages.characterPages)
      write(folder / file, html);
  }
  write(output, pages.page); // last: its links lead to pages already written
  return 0;
}

} // namespace crowd::cli
