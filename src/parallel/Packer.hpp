// Byte strings that carry a task's result between processes (a child's pipe, an MPI
// message): fields one after the other, each as <length>:<bytes>, numbers exactly (a double
// as its hexadecimal text, so a value crosses ranks bit for bit).
#pragma once

#include <cstddef>
#include <string>

namespace flexsens {

class Packer {
 public:
  Packer& text(const std::string& s);
  Packer& number(double v);
  Packer& integer(long long v);
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

/// Reads the fields back in the order they were packed; std::runtime_error when the bytes
/// end early or a field does not hold what is asked.
class Unpacker {
 public:
  explicit Unpacker(const std::string& bytes) : bytes_(bytes) {}
  std::string text();
  double number();
  long long integer();
  bool atEnd() const { return at_ == bytes_.size(); }

 private:
  const std::string& bytes_;
  size_t at_ = 0;
};

}  // namespace flexsens
