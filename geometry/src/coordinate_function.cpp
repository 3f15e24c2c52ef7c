#include "billiards/geometry/coordinate_function.hpp"

#include <ginac/ginac.h>
#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

namespace billiards {

namespace {

enum Code { op_const, op_x, op_y, op_add, op_mul, op_powi, op_pow, op_sin, op_cos, op_tan, op_asin, op_acos,
            op_atan, op_sinh, op_cosh, op_tanh, op_exp, op_log, op_abs, op_sign, op_atan2, op_sqrt };

/// The deepest stack a program may use (checked when compiling).
constexpr int max_depth = 64;

const GiNaC::realsymbol& sym_x() {
  static const GiNaC::realsymbol x("x");
  return x;
}
const GiNaC::realsymbol& sym_y() {
  static const GiNaC::realsymbol y("y");
  return y;
}

/// Compiles e into postfix instructions; `depth` tracks the stack height.
class Compiler {
 public:
  Compiler(const std::string& file, int line, const std::string& text) : file_(file), line_(line), text_(text) {}

  std::vector<CoordinateFunction::Op> run(const GiNaC::ex& e) {
    emit(e);
    return std::move(ops_);
  }

 private:
  void push(int code, double value = 0) {
    ops_.push_back({code, value});
    if (code == op_const || code == op_x || code == op_y) {
      if (++depth_ > max_depth) fail("is too deeply nested");
    } else if (code == op_add || code == op_mul || code == op_pow || code == op_atan2) {
      --depth_;
    }
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(file_, line_, "expression '" + text_ + "' " + why);
  }
  void emit(const GiNaC::ex& e) {
    using namespace GiNaC;
    if (!e.has(sym_x()) && !e.has(sym_y())) {
      const ex v = e.evalf();
      if (!is_a<numeric>(v) || !ex_to<numeric>(v).is_real()) fail("has a constant part that is not a real number");
      return push(op_const, ex_to<numeric>(v).to_double());
    }
    if (e.is_equal(sym_x())) return push(op_x);
    if (e.is_equal(sym_y())) return push(op_y);
    if (is_a<add>(e) || is_a<mul>(e)) {
      for (std::size_t i = 0; i < e.nops(); ++i) {
        emit(e.op(i));
        if (i > 0) push(is_a<add>(e) ? op_add : op_mul);
      }
      return;
    }
    if (is_a<power>(e)) {
      emit(e.op(0));
      const ex n = e.op(1);
      if (is_a<numeric>(n) && ex_to<numeric>(n).is_integer() && abs(ex_to<numeric>(n)) < 64)
        return push(op_powi, ex_to<numeric>(n).to_double());
      if (n.is_equal(numeric(1, 2))) return push(op_sqrt);
      emit(n);
      return push(op_pow);
    }
    if (is_a<function>(e)) {
      static const std::pair<const char*, int> unary[] = {
          {"sin", op_sin},   {"cos", op_cos},   {"tan", op_tan},   {"asin", op_asin}, {"acos", op_acos}, {"atan", op_atan},
          {"sinh", op_sinh}, {"cosh", op_cosh}, {"tanh", op_tanh}, {"exp", op_exp},   {"log", op_log},   {"abs", op_abs},
          {"csgn", op_sign}};
      const std::string name = ex_to<function>(e).get_name();
      if (name == "atan2" && e.nops() == 2) {
        emit(e.op(0));
        emit(e.op(1));
        return push(op_atan2);
      }
      for (const auto& [fname, code] : unary)
        if (name == fname && e.nops() == 1) {
          emit(e.op(0));
          return push(code);
        }
      fail("uses the function '" + name + "', which field expressions do not support");
    }
    std::ostringstream os;
    os << e;
    fail("has a part that cannot be evaluated: " + os.str());
  }

  std::string file_;
  int line_;
  std::string text_;
  std::vector<CoordinateFunction::Op> ops_;
  int depth_ = 0;
};

double evaluate(const std::vector<CoordinateFunction::Op>& program, double x, double y) {
  double st[max_depth];
  int top = -1;
  for (const auto& op : program) {
    switch (op.code) {
      case op_const: st[++top] = op.value; break;
      case op_x: st[++top] = x; break;
      case op_y: st[++top] = y; break;
      case op_add: st[top - 1] += st[top]; --top; break;
      case op_mul: st[top - 1] *= st[top]; --top; break;
      case op_pow: st[top - 1] = std::pow(st[top - 1], st[top]); --top; break;
      case op_atan2: st[top - 1] = std::atan2(st[top - 1], st[top]); --top; break;
      case op_powi: {
        const int n = int(op.value);
        const double b = st[top];
        double r = 1;
        for (int k = 0, m = std::abs(n); k < m; ++k) r *= b;
        st[top] = n < 0 ? 1 / r : r;
        break;
      }
      case op_sin: st[top] = std::sin(st[top]); break;
      case op_cos: st[top] = std::cos(st[top]); break;
      case op_tan: st[top] = std::tan(st[top]); break;
      case op_asin: st[top] = std::asin(st[top]); break;
      case op_acos: st[top] = std::acos(st[top]); break;
      case op_atan: st[top] = std::atan(st[top]); break;
      case op_sinh: st[top] = std::sinh(st[top]); break;
      case op_cosh: st[top] = std::cosh(st[top]); break;
      case op_tanh: st[top] = std::tanh(st[top]); break;
      case op_exp: st[top] = std::exp(st[top]); break;
      case op_log: st[top] = std::log(st[top]); break;
      case op_abs: st[top] = std::abs(st[top]); break;
      case op_sqrt: st[top] = std::sqrt(st[top]); break;
      case op_sign: st[top] = st[top] > 0 ? 1.0 : st[top] < 0 ? -1.0 : 0.0; break;
    }
  }
  return st[0];
}

/// The same text evaluated by muparser (the shape files' parser) must agree with the compiled
/// program at a few points: otherwise the two grammars read it differently.
void check_against_muparser(const std::vector<CoordinateFunction::Op>& program, const std::string& text,
                            const Expressions& params, const std::string& file, int line) {
  mu::Parser parser;
  double x = 0, y = 0;
  try {
    parser.DefineConst("pi", M_PI);
    parser.DefineConst("e", M_E);
    for (const auto& [name, value] : params.values()) parser.DefineConst(name, value);
    parser.DefineVar("x", &x);
    parser.DefineVar("y", &y);
    parser.SetExpr(text);
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(file, line, "bad expression '" + text + "': " + e.GetMsg());
  }
  const double points[][2] = {{0.3141, 0.5772}, {-0.7071, 0.2718}, {0.1234, -0.9876}, {1.4142, 1.7321}};
  for (const auto& p : points) {
    x = p[0];
    y = p[1];
    double expected;
    try {
      expected = parser.Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw InputError(file, line, "bad expression '" + text + "': " + e.GetMsg());
    }
    const double got = evaluate(program, x, y);
    if (!std::isfinite(expected) && !std::isfinite(got)) continue;  // e.g. log of a negative number
    if (!(std::abs(got - expected) <= 1e-12 * (1 + std::abs(expected))))
      throw InputError(file, line,
                       "expression '" + text + "' is read differently by the field parser and muparser (" +
                           std::to_string(got) + " and " + std::to_string(expected) + " at x = " +
                           std::to_string(x) + ", y = " + std::to_string(y) + "): add parentheses");
  }
}

}  // namespace

struct CoordinateFunction::Symbolic {
  GiNaC::ex e;
  std::string file;
  int line = 0;
};

CoordinateFunction::CoordinateFunction() : CoordinateFunction(std::make_shared<Symbolic>(Symbolic{0, "", 0})) {}

namespace {
/// GiNaC's parser reads past its argument list on a function called with none (`sqrt()`) and
/// crashes, so such a call is refused before GiNaC sees the text.
void refuse_empty_call(const std::string& text, const std::string& file, int line) {
  static const std::regex empty_call(R"(([A-Za-z_][A-Za-z0-9_]*)\s*\(\s*\))");
  if (std::smatch m; std::regex_search(text, m, empty_call))
    throw InputError(file, line, "bad expression '" + text + "': " + m[1].str() + "() has no argument");
}
}  // namespace

CoordinateFunction::CoordinateFunction(std::shared_ptr<const Symbolic> s) : symbolic_(std::move(s)) {
  std::ostringstream os;
  os << symbolic_->e;
  program_ = Compiler(symbolic_->file, symbolic_->line, os.str()).run(symbolic_->e);
}

CoordinateFunction::CoordinateFunction(const std::string& text, const Expressions& params, const std::string& file,
                                       int line) {
  GiNaC::symtab table;
  table["x"] = sym_x();
  table["y"] = sym_y();
  table["pi"] = GiNaC::Pi;
  table["e"] = GiNaC::exp(GiNaC::ex(1));
  for (const auto& [name, value] : params.values()) {
    if (name == "x" || name == "y")
      throw InputError(file, line, "parameter '" + name + "' hides the coordinate of the same name");
    table[name] = GiNaC::numeric(value);
  }
  refuse_empty_call(text, file, line);
  GiNaC::parser reader(table, true);
  auto s = std::make_shared<Symbolic>();
  s->file = file;
  s->line = line;
  try {
    s->e = reader(text);
  } catch (const std::exception& err) {
    std::string why = err.what();
    why = why.substr(0, why.find('\n'));
    if (why.rfind("find_or_insert_symbol: symbol \"", 0) == 0)
      why = "unknown name '" + why.substr(31, why.find('"', 31) - 31) + "' (the coordinates are x and y)";
    else if (why.rfind("GiNaC: ", 0) == 0)
      why = why.substr(7);
    throw InputError(file, line, "bad expression '" + text + "': " + why);
  }
  symbolic_ = s;
  program_ = Compiler(file, line, text).run(s->e);
  check_against_muparser(program_, text, params, file, line);
}

CoordinateFunction::~CoordinateFunction() = default;
CoordinateFunction::CoordinateFunction(const CoordinateFunction&) = default;
CoordinateFunction& CoordinateFunction::operator=(const CoordinateFunction&) = default;

double CoordinateFunction::operator()(const geometry::Vec2& p) const { return evaluate(program_, p.x(), p.y()); }

CoordinateFunction CoordinateFunction::derivative(int axis) const {
  const GiNaC::symbol& s = axis == 0 ? static_cast<const GiNaC::symbol&>(sym_x()) : sym_y();
  return CoordinateFunction(std::make_shared<Symbolic>(Symbolic{symbolic_->e.diff(s), symbolic_->file, symbolic_->line}));
}

std::string CoordinateFunction::text() const {
  std::ostringstream os;
  os << symbolic_->e;
  return os.str();
}

bool CoordinateFunction::constant() const { return !symbolic_->e.has(sym_x()) && !symbolic_->e.has(sym_y()); }

}  // namespace billiards
