// Placeholders of run-time values in assert messages (see MessageText.h).
#include "ir/MessageText.h"

#include "ir/Print.h"

namespace ldae::ir {

namespace {
constexpr char kMark = '\x1f';
} // namespace

std::string messagePlaceholder(size_t index, const std::string &format) {
  return kMark + std::to_string(index) + ":" + format + kMark;
}

std::vector<MessagePiece> splitMessage(const std::string &message) {
  std::vector<MessagePiece> pieces;
  size_t i = 0;
  while (i < message.size()) {
    size_t open = message.find(kMark, i);
    size_t close = open == std::string::npos ? open : message.find(kMark, open + 1);
    size_t colon = close == std::string::npos ? close : message.find(':', open);
    bool digits = colon != std::string::npos && colon < close &&
                  colon > open + 1 && colon - open <= 7;
    for (size_t k = open + 1; digits && k < colon; ++k)
      digits = message[k] >= '0' && message[k] <= '9';
    if (!digits) {
      pieces.push_back({message.substr(i), -1, ""});
      break;
    }
    if (open > i)
      pieces.push_back({message.substr(i, open - i), -1, ""});
    MessagePiece v;
    v.value = std::stoi(message.substr(open + 1, colon - open - 1));
    v.format = message.substr(colon + 1, close - colon - 1);
    pieces.push_back(std::move(v));
    i = close + 1;
  }
  return pieces;
}

namespace {

/// `String(e, ...)` as written for a placeholder's format.
std::string stringCallText(const std::string &e, const std::string &format) {
  if (!format.empty() && format[0] == '%')
    return "String(" + e + ", format = " + printString(format.substr(1)) + ")";
  // g<digits>,<width>,<left>: the defaults left out.
  std::string digits = "6", width = "0", left = "1";
  size_t a = format.find(','), b = format.rfind(',');
  if (format.size() > 1 && a != std::string::npos && b > a) {
    digits = format.substr(1, a - 1);
    width = format.substr(a + 1, b - a - 1);
    left = format.substr(b + 1);
  }
  std::string text = "String(" + e;
  if (digits != "6")
    text += ", significantDigits = " + digits;
  if (width != "0")
    text += ", minimumLength = " + width;
  if (left != "1")
    text += ", leftJustified = false";
  return text + ")";
}

} // namespace

std::string messageExpression(const std::string &message,
                              const std::vector<std::string> &valueText) {
  std::string out;
  for (const MessagePiece &p : splitMessage(message)) {
    out += out.empty() ? "" : " + ";
    out += p.value < 0 || size_t(p.value) >= valueText.size()
               ? printString(p.text)
               : stringCallText(valueText[size_t(p.value)], p.format);
  }
  return out.empty() ? printString("") : out;
}

} // namespace ldae::ir
