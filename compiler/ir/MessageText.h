// The message of an assert with values known only at run time: MSL builds
// them as "y = " + String(y) with y an unknown. Each such value shows in
// the text as a placeholder, "\x1f<index>:<format>\x1f", index into the
// assert's message values, format either "g<significantDigits>,
// <minimumLength>,<leftJustified>" (String's default form: an integral
// value as an integer, else %.<digits>g, padded) or "%<printf format>"
// (String(x, format = ...)). The runtime formats them the same way when
// the assert fails (runtime/src/events/Asserts.cpp; the ABI's
// assert_value_begin).
#pragma once

#include <string>
#include <vector>

namespace ldae::ir {

std::string messagePlaceholder(size_t index, const std::string &format);

struct MessagePiece {
  std::string text;   // literal text (value < 0)
  int value = -1;     // index into the message values
  std::string format; // the placeholder's format
};

/// The message cut into literal text and placeholders.
std::vector<MessagePiece> splitMessage(const std::string &message);

/// The message as a String expression: "text" + String(y) + ..., with
/// `valueText[k]` the printed message value k.
std::string messageExpression(const std::string &message,
                              const std::vector<std::string> &valueText);

} // namespace ldae::ir
