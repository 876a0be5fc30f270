// The files `syrof new` writes, as templates built into the command (their
// sources are cli/new_project/, generated into a C++ file by embed.cmake).
// "{{NAME}}", "{{SOURCE}}", "{{LANGUAGE}}" and "{{HINTS}}" are filled in by
// new_command.cpp.
#pragma once

#include <span>

namespace syrof::cli {

struct TemplateFile {
  const char* name;  ///< its name under cli/new_project/, e.g. "app.c" or "CMakeLists.txt.in"
  const char* text;
};

/// Every template, in a fixed order.
std::span<const TemplateFile> NewProjectTemplates();

}  // namespace syrof::cli
