#include "parallel/Packer.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace flexsens {

Packer& Packer::text(const std::string& s) {
  bytes_ += std::to_string(s.size());
  bytes_ += ':';
  bytes_ += s;
  return *this;
}

Packer& Packer::number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);  // exact: hexadecimal mantissa and exponent
  return text(buf);
}

Packer& Packer::integer(long long v) { return text(std::to_string(v)); }

std::string Unpacker::text() {
  const size_t colon = bytes_.find(':', at_);
  if (colon == std::string::npos || colon == at_ || colon - at_ > 19)
    throw std::runtime_error("malformed result message: no field length at byte " + std::to_string(at_));
  const unsigned long long n = std::stoull(bytes_.substr(at_, colon - at_));
  if (n > bytes_.size() - colon - 1)
    throw std::runtime_error("malformed result message: a field runs past its end at byte " + std::to_string(at_));
  std::string s = bytes_.substr(colon + 1, n);
  at_ = colon + 1 + n;
  return s;
}

double Unpacker::number() {
  const std::string s = text();
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end) throw std::runtime_error("malformed result message: '" + s + "' is not a number");
  return v;
}

long long Unpacker::integer() {
  const std::string s = text();
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || *end) throw std::runtime_error("malformed result message: '" + s + "' is not an integer");
  return v;
}

}  // namespace flexsens
