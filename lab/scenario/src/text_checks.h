// Checks on a scenario's raw text, made before the YAML parser sees it: the
// things the parser could choke on or that the tree builder cannot see.
#pragma once

#include <cstddef>
#include <string>

#include "diagnostics.h"
#include "syrof/lab/scenario/scenario.h"

namespace syrof::lab::scenario {

// Records the first problem in `diagnostics` and returns false when the
// text is longer than kMaxScenarioBytes; is not UTF-8 text (invalid bytes,
// control characters other than tab, CR and LF); indents a line with a tab;
// holds a second YAML document (a '---' line after content, or content
// after a '...' line); or nests flow collections ('[', '{') deeper than
// kMaxScenarioDepth. The last check runs before parsing because the parser
// recurses once per nested flow collection.
// `max_bytes` is the cap for a file of the family allowed more than a
// scenario (a scripted channel's lost_file).
bool CheckScenarioText(const std::string& text, Diagnostics& diagnostics, size_t max_bytes = kMaxScenarioBytes);

// The deepest flow-collection nesting in `text`, by a lexical scan that
// skips comments, quoted scalars, plain scalars and block scalars as the
// parser does. It errs towards counting: a bracket inside a multi-line
// quoted scalar or a block scalar's odd line counts. Contrived text (a
// quote character starting a continuation line of a plain scalar) can
// still hide brackets from it; the tree builder's own depth limit, checked
// on every collection event before the parser descends, catches those.
// Stops and returns as soon as the depth exceeds `limit`, with the 0-based
// offset of the bracket in `offset`.
int FlowDepth(const std::string& text, int limit, size_t& offset);

}  // namespace syrof::lab::scenario
