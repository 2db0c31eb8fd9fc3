// A small run folder written by hand for the view's unit tests: two robots "a" and "b", one
// obstacle, three trajectory samples each, links.csv, losses.csv.gz, connectivity.csv and
// metrics.csv rows.
#ifndef SITLNET_VIEW_TEST_RUN_FOLDER_FIXTURE_H_
#define SITLNET_VIEW_TEST_RUN_FOLDER_FIXTURE_H_

#include <string>

namespace sitlnet::view::testing {

// Writes the folder under the test's temporary folder; returns its path. `losses` is the
// text of losses.csv.gz after its header (gzipped here).
std::string WriteRunFolder(const std::string& name, const std::string& losses);

// Writes `text` to `path` (gzipped when `gzip`).
void WriteFile(const std::string& path, const std::string& text, bool gzip = false);

}  // namespace sitlnet::view::testing

#endif  // SITLNET_VIEW_TEST_RUN_FOLDER_FIXTURE_H_
