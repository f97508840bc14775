#pragma once
// The project's one version, project(VERSION) in the top-level CMakeLists.txt: what every program's
// --version prints, report.json and the status message carry, recordings name as their writer and
// the Debian packages are numbered by.

namespace vifusion {

/// "MAJOR.MINOR.PATCH", e.g. "0.1.0".
const char* versionString();

}  // namespace vifusion
