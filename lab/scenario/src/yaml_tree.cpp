#include "yaml_tree.h"

#include <sstream>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

namespace syrof::lab::scenario {

const YamlNode* YamlNode::Find(std::string_view key) const {
  for (size_t i = 0; i < keys.size(); ++i) {
    if (keys[i].scalar == key) return &values[i];
  }
  return nullptr;
}

namespace {

// Thrown by the handler to stop the parser at the first problem (the error
// itself is already in Diagnostics); caught in ReadYamlDocument and nowhere
// else. yaml-cpp's parser is exception-safe: it throws its own.
struct StopParsing {};

// Builds the tree from events. Each open map or list is a frame; a frame's
// node lives in its parent's vector, which does not grow while the frame is
// open (only the innermost container receives nodes), so the pointer stays
// valid.
class TreeBuilder final : public YAML::EventHandler {
 public:
  TreeBuilder(YamlNode& root, Diagnostics& diagnostics, size_t max_nodes)
      : root_(root), diagnostics_(diagnostics), max_nodes_(max_nodes) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}

  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    CheckAnchor(mark, anchor);
    YamlNode node;
    node.kind = YamlNode::Kind::kNull;
    Place(node, mark);
    Add(std::move(node));
  }

  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    Stop(mark, "aliases (*name) are not supported in scenarios" + Where());
  }

  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    CheckAnchor(mark, anchor);
    CheckTag(mark, tag);
    YamlNode node;
    node.kind = YamlNode::Kind::kScalar;
    Place(node, mark);
    node.scalar = value;
    // yaml-cpp tags a plain scalar "?" and a quoted one "!".
    node.quoted = tag == "!";
    Add(std::move(node));
  }

  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    Open(mark, tag, anchor, YamlNode::Kind::kSequence);
  }
  void OnSequenceEnd() override { frames_.pop_back(); }

  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    Open(mark, tag, anchor, YamlNode::Kind::kMap);
  }
  void OnMapEnd() override {
    if (!frames_.empty() && frames_.back().expecting_value) {
      // yaml-cpp closes a map after a key without a value only on malformed
      // input it reports itself; keep the tree consistent regardless.
      frames_.back().node->values.emplace_back();
    }
    frames_.pop_back();
  }

 private:
  struct Frame {
    YamlNode* node;
    std::string path;          // key path of this container, "" for the root
    bool expecting_value = false;  // maps: a key was read, its value is next
  };

  static void Place(YamlNode& node, const YAML::Mark& mark) {
    node.line = mark.line + 1;
    node.column = mark.column + 1;
  }

  [[noreturn]] void Stop(const YAML::Mark& mark, std::string message) {
    diagnostics_.Fail(mark.line + 1, mark.column + 1, std::move(message));
    throw StopParsing{};
  }

  // " (in 'robots.poses[2]')" for the container being filled, "" at the top.
  std::string Where() const {
    if (frames_.empty() || frames_.back().path.empty()) return "";
    return " (in '" + frames_.back().path + "')";
  }

  void CheckAnchor(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor) Stop(mark, "anchors (&name) are not supported in scenarios" + Where());
  }

  void CheckTag(const YAML::Mark& mark, const std::string& tag) {
    if (tag != "?" && tag != "!" && !tag.empty()) {
      Stop(mark, "explicit tags ('" + tag + "') are not supported in scenarios" + Where());
    }
  }

  // The key path a new node at the current place gets.
  std::string ChildPath() const {
    if (frames_.empty()) return "";
    const Frame& frame = frames_.back();
    if (frame.node->is_sequence()) {
      return frame.path + "[" + std::to_string(frame.node->values.size()) + "]";
    }
    const std::string& key = frame.node->keys.back().scalar;
    return frame.path.empty() ? key : frame.path + "." + key;
  }

  void Open(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor, YamlNode::Kind kind) {
    CheckAnchor(mark, anchor);
    CheckTag(mark, tag);
    if (static_cast<int>(frames_.size()) + 1 > kMaxScenarioDepth) {
      Stop(mark, "maps and lists nest more than " + std::to_string(kMaxScenarioDepth) + " deep" + Where());
    }
    if (!frames_.empty() && frames_.back().node->is_map() && !frames_.back().expecting_value) {
      Stop(mark, "a map key must be a plain name, not a map or a list" + Where());
    }
    std::string path = ChildPath();
    YamlNode node;
    node.kind = kind;
    Place(node, mark);
    YamlNode* placed = Add(std::move(node));
    frames_.push_back(Frame{placed, std::move(path)});
  }

  // Puts a finished node (or a container about to be filled) in place and
  // returns where it now lives.
  YamlNode* Add(YamlNode node) {
    if (++nodes_ > max_nodes_) {
      diagnostics_.Fail(node.line, node.column,
                        "holds more than " + std::to_string(max_nodes_) + " maps, lists and values" + Where());
      throw StopParsing{};
    }
    if (frames_.empty()) {
      if (has_root_) Stop(YAML::Mark(), "more than one top-level node");
      has_root_ = true;
      root_ = std::move(node);
      return &root_;
    }
    Frame& frame = frames_.back();
    YamlNode& container = *frame.node;
    if (container.is_sequence()) {
      container.values.push_back(std::move(node));
      return &container.values.back();
    }
    if (frame.expecting_value) {
      frame.expecting_value = false;
      container.values.push_back(std::move(node));
      return &container.values.back();
    }
    if (!node.is_scalar()) {
      diagnostics_.Fail(node.line, node.column, "a map key must be a plain name" + Where());
      throw StopParsing{};
    }
    if (container.Find(node.scalar) != nullptr) {
      diagnostics_.Fail(node.line, node.column, "duplicate key '" + node.scalar + "'" + Where());
      throw StopParsing{};
    }
    frame.expecting_value = true;
    container.keys.push_back(std::move(node));
    return &container.keys.back();
  }

  YamlNode& root_;
  Diagnostics& diagnostics_;
  std::vector<Frame> frames_;
  bool has_root_ = false;
  const size_t max_nodes_;
  size_t nodes_ = 0;
};

}  // namespace

bool ReadYamlDocument(const std::string& text, YamlNode& root, Diagnostics& diagnostics, size_t max_nodes) {
  root = YamlNode{};
  root.line = 1;
  root.column = 1;
  std::istringstream stream(text);
  try {
    YAML::Parser parser(stream);
    TreeBuilder builder(root, diagnostics, max_nodes);
    // One call: the text holds at most one document (CheckScenarioText), and
    // calling again until it returns false is what can loop forever.
    parser.HandleNextDocument(builder);
  } catch (const StopParsing&) {
    return false;
  } catch (const YAML::Exception& error) {
    const int line = error.mark.is_null() ? 0 : error.mark.line + 1;
    const int column = error.mark.is_null() ? 0 : error.mark.column + 1;
    // An alias reaches the handler only after its anchor, which is refused
    // first; an alias to nothing fails inside the parser with this message.
    if (error.msg == YAML::ErrorMsg::UNKNOWN_ANCHOR) {
      return diagnostics.Fail(line, column, "aliases (*name) are not supported in scenarios");
    }
    return diagnostics.Fail(line, column, "YAML syntax error: " + error.msg);
  }
  return true;
}

}  // namespace syrof::lab::scenario
