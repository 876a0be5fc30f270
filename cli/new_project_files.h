// The files `syrof new` and `syrof assignment new` write, as templates built
// into the command (their sources are cli/new_project/ and
// cli/new_assignment/, generated into C++ files by
// cli/new_project/embed.cmake). "{{NAME}}", "{{SOURCE}}", "{{LANGUAGE}}" and
// "{{HINTS}}" are filled in by new_command.cpp and
// assignment_new_command.cpp.
#pragma once

#include <span>

namespace syrof::cli {

struct TemplateFile {
  const char* name;  ///< its name under its folder, e.g. "app.c" or "CMakeLists.txt.in"
  const char* text;
};

/// Every template of `syrof new` (cli/new_project/), in a fixed order.
std::span<const TemplateFile> NewProjectTemplates();

/// Every template of `syrof assignment new` (cli/new_assignment/), in a fixed order.
std::span<const TemplateFile> NewAssignmentTemplates();

}  // namespace syrof::cli
