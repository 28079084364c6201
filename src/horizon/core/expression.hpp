#pragma once
// A number that may vary in time and space: a constant, or a muParser expression in
// t, x, y, z (reference coordinates). Evaluating a constant costs nothing.
#include <memory>
#include <string>

namespace horizon {

class Expression {
 public:
  Expression() = default;  // the constant 0
  explicit Expression(double value) : value_(value) {}
  // Compiles text; throws horizon::Error with muParser's message if it does not parse.
  explicit Expression(const std::string& text);

  bool is_constant() const { return !parser_; }
  const std::string& text() const { return text_; }
  double operator()(double t, double x = 0, double y = 0, double z = 0) const;

 private:
  struct Parser;
  std::shared_ptr<Parser> parser_;
  std::string text_;
  double value_ = 0;
};

}  // namespace horizon
