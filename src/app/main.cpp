// octarc: octopole arc search for strong gravitational lenses, SExtractor-compatible.

#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "octarc/app/CommandLine.h"
#include "octarc/app/Commands.h"
#include "octarc/cluster/Cluster.h"
#include "octarc/core/Error.h"
#include "octarc/core/Format.h"
#include "octarc/core/Interrupt.h"

namespace {

// The three simulate commands, as both usages list them.
constexpr const char* kSimulateCommands =
    "  simulate lenses -n N --seed S -o OUT.fits [options]\n"
    "      simulated galaxy-galaxy lenses through the detector and measurements\n"
    "  simulate field -o FIELD.fits [options]\n"
    "      a survey-like field with injected lenses, weight map and truth list\n"
    "  simulate database IMAGE -o CATALOG.fits [options]\n"
    "      cut a source-galaxy database (RealGalaxyCatalog format) out of a deep image\n";

void printUsage() {
  std::cout << "Usage: octarc COMMAND [arguments]\n"
               "\n"
               "Commands:\n"
               "  measure IMAGE -SEGMENTATION_NAME seg.fits[,...] [-c file.sex] [-KEY value ...]\n"
               "      measure the objects of SExtractor segmentation check-images\n"
               "  detect IMAGE [-c file.sex] [-KEY value ...]\n"
               "      detect at every threshold in one pass and measure every object\n"
            << kSimulateCommands
            << "  calibrate SIM.fits [...] [-c file] [-KEY value ...]\n"
               "      lensing fractions, distributions, noise-only threshold and the occupation\n"
               "      grid of simulated arcs, with check-plots\n"
               "  search IMAGE [-c file] [-KEY value ...]\n"
               "      ranked lens candidates: catalog, DS9 regions, stamps and a vetting page\n"
               "  batch MANIFEST [-c file] [-KEY value ...]\n"
               "      search every tile of a survey (resumable; under mpirun or srun on many\n"
               "      ranks, or as a job array), and the survey's candidates\n"
               "  grades CATALOG GRADES.csv -o OUT.fits\n"
               "      the grades of a vetting page merged into the catalog (a GRADE column)\n"
               "  inject IMAGE [-c file] [-KEY value ...]\n"
               "      completeness against spurious candidates per deg2 on the image, by\n"
               "      injected lenses\n"
               "  demo [options]\n"
               "      simulate a field with lenses, detect them and report\n"
               "\n"
               "`octarc COMMAND -h` describes a command; `-dd` prints its configuration keys and\n"
               "`-dp` its catalog columns.\n";
}

void printSimulateUsage() {
  std::cout
      << "Usage: octarc simulate lenses|field|database [options]\n"
         "\n"
      << kSimulateCommands
      << "\n"
         "`octarc simulate lenses -h` describes one of them; -d, -dd, -dp and -v are theirs.\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    printUsage();
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "-v" || args[0] == "--version") {
    std::cout << "octarc version " << octarc::octarcVersion() << "\n";
    return 0;
  }
  const std::string command = args[0];
  const std::string shown = octarc::printableMessage(command, 40);  // typed by the user
  args.erase(args.begin());
  // Ctrl-C (and SIGTERM, SIGHUP) removes the run's temporary outputs before the process ends.
  const bool simulate = command == "simulate" && !args.empty();
  octarc::installInterruptCleanup("octarc " + command + (simulate ? " " + args[0] : ""));
  try {
    if (command == "measure") return octarc::runMeasure(args);
    if (command == "detect") return octarc::runDetect(args);
    if (command == "demo") return octarc::runDemo(args);
    if (command == "inject") return octarc::runInject(args);
    if (command == "calibrate") return octarc::runCalibrate(args);
    if (command == "search") return octarc::runSearch(args);
    if (command == "batch") return octarc::runBatch(args);
    if (command == "grades") return octarc::runGrades(args);
    if (command == "simulate") {
      const std::string what = args.empty() ? "" : args[0];
      if (!args.empty()) args.erase(args.begin());
      if (what == "lenses") return octarc::runSimulateLenses(args);
      if (what == "field") return octarc::runSimulateField(args);
      if (what == "database") return octarc::runBuildDatabase(args);
      if (what == "-h" || what == "--help") {
        printSimulateUsage();
        return 0;
      }
      if (what == "-v" || what == "--version") {
        std::cout << "octarc simulate version " << octarc::octarcVersion() << "\n";
        return 0;
      }
      std::cerr << "octarc simulate: say what to simulate: lenses, field or database "
                   "(try octarc -h)\n";
      return 2;
    }
    std::cerr << "octarc: unknown command '" << shown << "' (try octarc -h)\n";
    return 2;
  } catch (const octarc::PeerFailed&) {
    return 1;  // another rank of the MPI job failed first and said why
  } catch (const octarc::Error& e) {
    // The last guard: whatever a message quotes from a file, it reaches the terminal as one
    // printable line of reasonable length.
    std::cerr << "octarc " << shown << ": error: " << octarc::printableMessage(e.what()) << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "octarc " << shown << ": error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "octarc " << shown << ": internal error: " << octarc::printableMessage(e.what())
              << "\n";
    return 3;
  }
}
