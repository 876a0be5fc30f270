// lab/message: the payload check and the decoder (the YAML
// reader's errors are tested with the assignment file,
// tests/grader/assignment/assignment_test.cpp).
#include "syrof/lab/message/message_format.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace syrof::lab::message {
namespace {

MessageFormat Fields(std::vector<std::pair<std::string, FieldType>> fields) {
  MessageFormat format;
  format.none = false;
  for (auto& [name, type] : fields) {
    format.fields.push_back({name, type, format.length});
    format.length += FieldBytes(type);
  }
  return format;
}

TEST(MessageFormatTest, NoneAcceptsOnlyTheEmptyPayload) {
  const MessageFormat none;
  EXPECT_FALSE(CheckPayload(none, 0).has_value());
  EXPECT_EQ(CheckPayload(none, 1).value_or(Error{}).message, "1 bytes, but the format is none (send nothing)");
  EXPECT_TRUE(DecodePayload(none, std::vector<uint8_t>{}).empty());
}

TEST(MessageFormatTest, AFixedFormatAcceptsItsLengthOrNothing) {
  const MessageFormat charge = Fields({{"charge", FieldType::kU16Be}});
  EXPECT_FALSE(CheckPayload(charge, 0).has_value());
  EXPECT_FALSE(CheckPayload(charge, 2).has_value());
  EXPECT_EQ(CheckPayload(charge, 1).value_or(Error{}).message, "1 bytes, but the format has 2");
  EXPECT_EQ(CheckPayload(charge, 10).value_or(Error{}).message, "10 bytes, but the format has 2");  // a refused sendMessageData
}

TEST(MessageFormatTest, TheReadmeExampleDecodes) {
  // assignments/strongest/README.md: charge 870 is 0x03 0x66.
  const MessageFormat charge = Fields({{"charge", FieldType::kU16Be}});
  const std::vector<FieldValue> values = DecodePayload(charge, std::vector<uint8_t>{0x03, 0x66});
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values[0].name, "charge");
  EXPECT_EQ(values[0].value, 870);
  EXPECT_TRUE(DecodePayload(charge, std::vector<uint8_t>{0x03}).empty());
}

TEST(MessageFormatTest, EveryTypeDecodesItsByteOrderAndSign) {
  const MessageFormat format = Fields({{"a", FieldType::kI8},
                                       {"b", FieldType::kU16Le},
                                       {"c", FieldType::kI16Be},
                                       {"d", FieldType::kI32Le}});
  ASSERT_EQ(format.length, 9u);
  const std::vector<uint8_t> payload = {0xFF, 0x34, 0x12, 0xFF, 0xFE, 0xFE, 0xFF, 0xFF, 0xFF};
  const std::vector<FieldValue> values = DecodePayload(format, payload);
  ASSERT_EQ(values.size(), 4u);
  EXPECT_EQ(values[0].value, -1);
  EXPECT_EQ(values[1].value, 0x1234);
  EXPECT_EQ(values[2].value, -2);
  EXPECT_EQ(values[3].value, -2);
  const MessageFormat wide = Fields({{"u", FieldType::kU32Be}, {"v", FieldType::kU8}});
  const std::vector<FieldValue> wide_values = DecodePayload(wide, std::vector<uint8_t>{0xFF, 0xFF, 0xFF, 0xFE, 0x80});
  ASSERT_EQ(wide_values.size(), 2u);
  EXPECT_EQ(wide_values[0].value, 4294967294);
  EXPECT_EQ(wide_values[1].value, 128);
}

}  // namespace
}  // namespace syrof::lab::message
