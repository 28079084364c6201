#include "horizon/core/expression.hpp"

#include <muParser.h>

#include <cmath>
#include <mutex>

#include "horizon/core/error.hpp"

namespace horizon {

// muParser binds variables by address, so each Expression owns its variables.
// A parser is not safe to share between threads; the mutex makes concurrent calls
// correct (loads are evaluated on a few particles, outside the bond loop).
struct Expression::Parser {
  mu::Parser parser;
  double t = 0, x = 0, y = 0, z = 0;
  std::mutex mutex;
};

Expression::Expression(const std::string& text) : parser_(std::make_shared<Parser>()), text_(text) {
  try {
    auto& p = parser_->parser;
    p.DefineVar("t", &parser_->t);
    p.DefineVar("x", &parser_->x);
    p.DefineVar("y", &parser_->y);
    p.DefineVar("z", &parser_->z);
    p.DefineConst("pi", 3.14159265358979323846);
    // <cmath> functions muParser lacks, for Peridigm's C-style function strings
    // (deck/peridigm/function_string.hpp); atan2 is muParser's own.
    p.DefineFun("floor", static_cast<double (*)(double)>(std::floor));
    p.DefineFun("ceil", static_cast<double (*)(double)>(std::ceil));
    p.DefineFun("fmod", static_cast<double (*)(double, double)>(std::fmod));
    p.SetExpr(text);
    value_ = p.Eval();  // parse now so that errors surface while reading the deck
    // A text without variables is a constant: drop the parser.
    if (p.GetUsedVar().empty()) parser_.reset();
  } catch (const mu::Parser::exception_type& e) {
    throw Error("cannot parse expression '" + text + "': " + e.GetMsg());
  }
}

double Expression::operator()(double t, double x, double y, double z) const {
  if (!parser_) return value_;
  std::lock_guard<std::mutex> lock(parser_->mutex);
  parser_->t = t;
  parser_->x = x;
  parser_->y = y;
  parser_->z = z;
  return parser_->parser.Eval();
}

}  // namespace horizon
