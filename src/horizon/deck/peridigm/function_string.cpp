#include "horizon/deck/peridigm/function_string.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace horizon::peridigm {

namespace {

// The grammar read here is the part of C that Peridigm's run-time compiler (Trilinos
// RTCompiler, as described in Peridigm's users' guide, SAND2012-7800) evaluates in its
// decks: statements `name = expr;` (with an optional `double`/`float`/`int` type),
// `+= -= *= /=`, `if (...) stmt [else stmt]` with braces, and expressions with C's
// operators and precedence, `^` as the power (the decks write `(z/0.05-1)^2`) and the
// functions of <cmath> listed in kFunctions. The inputs are x, y, z, t; the result is
// `value`. Every value is kept as muParser text, fully parenthesised, so muParser's own
// precedence never matters; an `if` merges the two paths into `(c) ? (a) : (b)`.

struct Token {
  enum Kind { number, name, op, end } kind;
  std::string text;
  std::size_t at;
};

std::vector<Token> lex(const std::string& s) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < s.size()) {
    const char c = s[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '\\' && i + 1 < s.size() && (s[i + 1] == '{' || s[i + 1] == '}')) {
      // `\{` and `\}`: the escapes Peridigm's YAML decks carry for braces.
      out.push_back({Token::op, std::string(1, s[i + 1]), i});
      i += 2;
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      const char* begin = s.c_str() + i;
      char* end = nullptr;
      std::strtod(begin, &end);
      const std::size_t n = static_cast<std::size_t>(end - begin);
      out.push_back({Token::number, s.substr(i, n), i});
      i += n;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t j = i;
      while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
      out.push_back({Token::name, s.substr(i, j - i), i});
      i = j;
    } else {
      static const char* two[] = {"<=", ">=", "==", "!=", "&&", "||", "+=", "-=", "*=", "/="};
      std::string t(1, c);
      for (const char* w : two)
        if (s.compare(i, 2, w) == 0) t = w;
      if (t.size() == 1 && std::string("+-*/%^<>=!(){};,?:").find(c) == std::string::npos)
        throw FunctionStringError(i, fmt::format("unexpected character '{}'", c));
      out.push_back({Token::op, t, i});
      i += t.size();
    }
  }
  out.push_back({Token::end, "", s.size()});
  return out;
}

// Functions and their muParser spelling and number of arguments.
struct Function {
  const char* muparser;
  int arity;
};
const std::map<std::string, Function> kFunctions = {
    {"sin", {"sin", 1}},    {"cos", {"cos", 1}},     {"tan", {"tan", 1}},     {"asin", {"asin", 1}},
    {"acos", {"acos", 1}},  {"atan", {"atan", 1}},   {"sinh", {"sinh", 1}},   {"cosh", {"cosh", 1}},
    {"tanh", {"tanh", 1}},  {"exp", {"exp", 1}},     {"sqrt", {"sqrt", 1}},   {"abs", {"abs", 1}},
    {"fabs", {"abs", 1}},   {"log", {"ln", 1}},      {"log10", {"log10", 1}}, {"atan2", {"atan2", 2}},
    {"pow", {"^", 2}},      {"min", {"min", 2}},     {"max", {"max", 2}},     {"floor", {"floor", 1}},
    {"ceil", {"ceil", 1}},  {"fmod", {"fmod", 2}},
};

struct Variable {
  std::string expr;      // its value, as muParser text
  bool partial = false;  // set on one path of an if only
  std::size_t set_at = 0;
};

class Translator {
 public:
  explicit Translator(const std::string& text) : tokens_(lex(text)) {}

  std::string program() {
    // A bare expression (no statement) is the value itself.
    if (!has_statement()) {
      std::string e = expression();
      expect_end();
      return e;
    }
    while (peek().kind != Token::end) statement();
    const auto it = env_.find("value");
    if (it == env_.end()) throw FunctionStringError(0, "the function string never sets 'value'");
    if (it->second.partial)
      throw FunctionStringError(it->second.set_at, "'value' is set on one branch of an if only; set it on both (or "
                                                   "before the if)");
    return it->second.expr;
  }

 private:
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  std::map<std::string, Variable> env_;

  const Token& peek(std::size_t ahead = 0) const { return tokens_[std::min(pos_ + ahead, tokens_.size() - 1)]; }
  const Token& next() { return tokens_[pos_ < tokens_.size() - 1 ? pos_++ : pos_]; }
  bool is(const char* op) const { return peek().kind == Token::op && peek().text == op; }
  bool accept(const char* op) {
    if (!is(op)) return false;
    ++pos_;
    return true;
  }
  [[noreturn]] void fail_here(const std::string& expected) const {
    const Token& t = peek();
    throw FunctionStringError(t.at, fmt::format("expected {}, found {}", expected,
                                                t.kind == Token::end ? std::string("the end") : "'" + t.text + "'"));
  }
  void expect(const char* op) {
    if (!accept(op)) fail_here(fmt::format("'{}'", op));
  }
  void expect_end() const {
    if (peek().kind != Token::end) fail_here("the end of the expression");
  }
  bool has_statement() const {
    for (std::size_t i = 0; i + 1 < tokens_.size(); ++i) {
      const Token& t = tokens_[i];
      if (t.kind == Token::op && (t.text == ";" || t.text == "=" || t.text == "{" || t.text == "+=" ||
                                  t.text == "-=" || t.text == "*=" || t.text == "/="))
        return true;
      if (t.kind == Token::name && t.text == "if") return true;
    }
    return false;
  }

  // --- statements ---
  void statement() {
    if (accept(";")) return;
    if (accept("{")) {
      while (!is("}")) {
        if (peek().kind == Token::end) fail_here("'}'");
        statement();
      }
      ++pos_;
      return;
    }
    const Token& t = peek();
    if (t.kind == Token::name && t.text == "if") {
      ++pos_;
      expect("(");
      const std::string cond = expression();
      expect(")");
      const auto before = env_;
      statement();
      auto then_env = env_;
      env_ = before;
      if (peek().kind == Token::name && peek().text == "else") {
        ++pos_;
        statement();
      }
      merge(cond, before, then_env, env_);
      return;
    }
    if (t.kind == Token::name && (t.text == "double" || t.text == "float" || t.text == "int")) ++pos_;
    const Token& target = peek();
    if (target.kind != Token::name) fail_here("a statement such as 'value = ...;'");
    if (target.text == "x" || target.text == "y" || target.text == "z" || target.text == "t" ||
        kFunctions.count(target.text) || target.text == "else")
      throw FunctionStringError(target.at, "cannot assign to '" + target.text + "'");
    ++pos_;
    const Token& op = peek();
    if (!(is("=") || is("+=") || is("-=") || is("*=") || is("/="))) fail_here("'=' after '" + target.text + "'");
    ++pos_;
    std::string e = expression();
    if (op.text != "=") e = "(" + read(target) + op.text.substr(0, 1) + e + ")";
    if (peek().kind != Token::end) expect(";");  // the last statement's ';' may be left out
    env_[target.text] = {e, false, target.at};
  }

  // After `if (cond) A else B`: each variable is cond ? (its value after A) : (after B).
  void merge(const std::string& cond, const std::map<std::string, Variable>& before,
             const std::map<std::string, Variable>& a, const std::map<std::string, Variable>& b) {
    std::set<std::string> names;
    for (const auto& [k, v] : a) names.insert(k);
    for (const auto& [k, v] : b) names.insert(k);
    std::map<std::string, Variable> out;
    for (const auto& name : names) {
      const auto ia = a.find(name), ib = b.find(name);
      if (ia != a.end() && ib != b.end()) {
        if (ia->second.expr == ib->second.expr)
          out[name] = ia->second;
        else
          out[name] = {"(" + cond + "?" + ia->second.expr + ":" + ib->second.expr + ")",
                       ia->second.partial || ib->second.partial, ia->second.set_at};
      } else {
        // Set on one path only (an if without else, or a new name in one branch).
        const Variable& v = ia != a.end() ? ia->second : ib->second;
        out[name] = {v.expr, true, v.set_at};
        (void)before;
      }
    }
    env_ = std::move(out);
  }

  std::string read(const Token& name) const {
    const std::string& n = name.text;
    if (n == "x" || n == "y" || n == "z" || n == "t") return n;
    if (n == "pi" || n == "M_PI") return "pi";
    const auto it = env_.find(n);
    if (it == env_.end())
      throw FunctionStringError(name.at, "unknown name '" + n + "' (the inputs are x, y, z and t; other names must "
                                                                "be set before they are read)");
    if (it->second.partial)
      throw FunctionStringError(name.at, "'" + n + "' is set on one branch of an if only, so it may be unset here");
    return it->second.expr;
  }

  // --- expressions, C's precedence ---
  std::string expression() {
    std::string c = logical_or();
    if (accept("?")) {
      std::string a = expression();
      expect(":");
      std::string b = expression();
      return "(" + c + "?" + a + ":" + b + ")";
    }
    return c;
  }
  std::string binary_chain(std::string (Translator::*lower)(), std::initializer_list<const char*> ops) {
    std::string left = (this->*lower)();
    for (;;) {
      const char* found = nullptr;
      for (const char* o : ops)
        if (is(o)) found = o;
      if (!found) return left;
      ++pos_;
      const std::string right = (this->*lower)();
      if (std::string(found) == "%")
        left = "fmod(" + left + "," + right + ")";
      else
        left = "(" + left + found + right + ")";
    }
  }
  std::string logical_or() { return binary_chain(&Translator::logical_and, {"||"}); }
  std::string logical_and() { return binary_chain(&Translator::equality, {"&&"}); }
  std::string equality() { return binary_chain(&Translator::relation, {"==", "!="}); }
  std::string relation() { return binary_chain(&Translator::sum, {"<", "<=", ">", ">="}); }
  std::string sum() { return binary_chain(&Translator::product, {"+", "-"}); }
  std::string product() { return binary_chain(&Translator::unary, {"*", "/", "%"}); }
  std::string unary() {
    if (accept("-")) return "(-" + unary() + ")";
    if (accept("+")) return unary();
    if (accept("!")) return "(" + unary() + "==0)";
    return power();
  }
  std::string power() {
    std::string base = primary();
    if (accept("^")) return "(" + base + "^" + unary() + ")";  // right-associative, binds tighter than unary minus
    return base;
  }
  std::string primary() {
    const Token t = peek();
    if (t.kind == Token::number) {
      ++pos_;
      return fmt::format("{}", std::strtod(t.text.c_str(), nullptr));
    }
    if (accept("(")) {
      std::string e = expression();
      expect(")");
      return "(" + e + ")";
    }
    if (t.kind != Token::name) fail_here("a number, a name or '('");
    ++pos_;
    if (!accept("(")) return "(" + read(t) + ")";
    const auto f = kFunctions.find(t.text);
    if (f == kFunctions.end()) {
      std::string known;
      for (const auto& [k, v] : kFunctions) known += (known.empty() ? "" : ", ") + k;
      throw FunctionStringError(t.at, "unknown function '" + t.text + "'; known: " + known);
    }
    std::vector<std::string> args;
    if (!is(")")) {
      args.push_back(expression());
      while (accept(",")) args.push_back(expression());
    }
    expect(")");
    if (static_cast<int>(args.size()) != f->second.arity)
      throw FunctionStringError(t.at, fmt::format("{} takes {} argument{}, found {}", t.text, f->second.arity,
                                                  f->second.arity == 1 ? "" : "s", args.size()));
    if (std::string(f->second.muparser) == "^") return "(" + args[0] + "^" + args[1] + ")";
    std::string call = std::string(f->second.muparser) + "(";
    for (std::size_t i = 0; i < args.size(); ++i) call += (i ? "," : "") + args[i];
    return call + ")";
  }
};

}  // namespace

std::string function_string_to_muparser(const std::string& text) { return Translator(text).program(); }

std::string unescape_peridigm_braces(const std::string& yaml_text) {
  // Only Peridigm decks: a line that starts with the key Peridigm.
  const bool peridigm = yaml_text.rfind("Peridigm:", 0) == 0 || yaml_text.find("\nPeridigm:") != std::string::npos;
  if (!peridigm || yaml_text.find('\\') == std::string::npos) return yaml_text;
  std::string out = yaml_text;
  for (std::size_t i = 0; i + 1 < out.size(); ++i) {
    if (out[i] != '\\') continue;
    if (out[i + 1] == '{' || out[i + 1] == '}') out[i] = ' ';
    else ++i;  // an escaped character (`\\`, `\"`, ...) stays as YAML reads it
  }
  return out;
}

}  // namespace horizon::peridigm
