// scenario_doc: writes docs/scenario.md's field tables from scenario.proto's options, so the
// page cannot drift from the schema; with --check it writes nothing and fails (exit 1) when the
// page differs from what it would write. The test docs.scenario_md runs the check.
// Usage: scenario_doc [--check] docs/scenario.md
#include <cstring>
#include <fstream>
#include <iostream>

#include "scenario/field_table.h"
#include "scenario/scenario.h"

int main(int argc, char** argv) {
  const bool check = argc == 3 && std::strcmp(argv[1], "--check") == 0;
  if (argc != 2 && !check) {
    std::cerr << "usage: scenario_doc [--check] docs/scenario.md\n";
    return 2;
  }
  const std::string path = argv[argc - 1];
  try {
    const std::string page = sitlnet::ReadFileOrThrow(path, "page");
    const std::string generated = sitlnet::WithFieldTables(page);
    if (check) {
      if (generated == page) return 0;
      std::cerr << path << ": field tables differ from scenario.proto's options; run "
                << "build/bin/scenario_doc " << path << "\n";
      return 1;
    }
    std::ofstream(path) << generated;
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "scenario_doc: " << error.what() << "\n";
    return 2;
  }
}
