#include "frontend/nesting.h"

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace rcxc::frontend {
namespace {

using ast::Expr;
using ast::Stmt;

// The direct children of a node, for walks that keep their own stack.
struct Children {
  std::vector<Expr*> exprs;
  std::vector<Stmt*> stmts;
  void clear() {
    exprs.clear();
    stmts.clear();
  }
};

template <class... F>
struct Overload : F... {
  using F::operator()...;
};
template <class... F>
Overload(F...) -> Overload<F...>;

void children_of(Expr& e, Children& out) {
  std::visit(Overload{
                 [&](ast::Unary& u) { out.exprs.push_back(u.operand.get()); },
                 [&](ast::Binary& b) { out.exprs.insert(out.exprs.end(), {b.lhs.get(), b.rhs.get()}); },
                 [&](ast::Assign& a) { out.exprs.insert(out.exprs.end(), {a.target.get(), a.value.get()}); },
                 [&](ast::Conditional& c) {
                   out.exprs.insert(out.exprs.end(), {c.cond.get(), c.then_value.get(), c.else_value.get()});
                 },
                 [&](ast::Call& c) {
                   for (auto& a : c.args) out.exprs.push_back(&a);
                 },
                 [&](ast::Source& s) { out.exprs.insert(out.exprs.end(), {s.type.get(), s.arg.get()}); },
                 [&](ast::SourceArg& s) { out.exprs.push_back(s.operand.get()); },
                 [&](ast::TypeOf& t) { out.exprs.push_back(t.operand.get()); },
                 [](auto&) {},
             },
             e.node);
}

void children_of(Stmt& s, Children& out) {
  auto expr = [&](Expr& e) { out.exprs.push_back(&e); };
  auto stmt = [&](ast::StmtBox& b) { out.stmts.push_back(b.get()); };
  std::visit(Overload{
                 [&](ast::Block& b) {
                   for (auto& st : b.stmts) out.stmts.push_back(&st);
                 },
                 [&](ast::DeclStmt& d) {
                   for (auto& v : d.vars)
                     if (v.init) expr(*v.init);
                 },
                 [&](ast::ExprStmt& e) { expr(e.expr); },
                 [&](ast::If& i) {
                   expr(i.cond);
                   stmt(i.then_branch);
                   if (i.else_branch) stmt(*i.else_branch);
                 },
                 [&](ast::While& w) {
                   expr(w.cond);
                   stmt(w.body);
                 },
                 [&](ast::DoWhile& d) {
                   stmt(d.body);
                   expr(d.cond);
                 },
                 [&](ast::Until& u) {
                   expr(u.cond);
                   stmt(u.body);
                 },
                 [&](ast::For& f) {
                   if (f.init) stmt(*f.init);
                   if (f.cond) expr(*f.cond);
                   if (f.step) expr(*f.step);
                   stmt(f.body);
                 },
                 [&](ast::Repeat& r) {
                   expr(r.count);
                   stmt(r.body);
                 },
                 [&](ast::Switch& sw) {
                   expr(sw.value);
                   stmt(sw.body);
                 },
                 [&](ast::Case& c) {
                   expr(c.value);
                   stmt(c.body);
                 },
                 [&](ast::Default& d) { stmt(d.body); },
                 [&](ast::Labeled& l) { stmt(l.body); },
                 [&](ast::Asm& a) {
                   for (auto& item : a.items) {
                     if (auto* b = std::get_if<ast::AsmByte>(&item)) expr(b->value);
                     if (auto* i = std::get_if<ast::AsmInstr>(&item))
                       for (auto& op : i->operands) expr(op);
                   }
                 },
                 [](auto&) {},
             },
             s.node);
}

// The first node deeper than kMaxNesting below `root` (depth 1), if any.
template <class Root>
const SourceSpan* too_deep(Root& root) {
  struct Item {
    Expr* expr;
    Stmt* stmt;
    int depth;
  };
  std::vector<Item> stack;
  if constexpr (std::is_same_v<Root, Expr>)
    stack.push_back({&root, nullptr, 1});
  else
    stack.push_back({nullptr, &root, 1});
  Children children;
  while (!stack.empty()) {
    Item item = stack.back();
    stack.pop_back();
    if (item.depth > kMaxNesting) return item.expr ? &item.expr->span : &item.stmt->span;
    children.clear();
    if (item.expr)
      children_of(*item.expr, children);
    else
      children_of(*item.stmt, children);
    // Reversed, so that the first child in the source is looked at first and
    // the error lands on the first place that is too deep.
    for (auto s = children.stmts.rbegin(); s != children.stmts.rend(); ++s) stack.push_back({nullptr, *s, item.depth + 1});
    for (auto e = children.exprs.rbegin(); e != children.exprs.rend(); ++e) stack.push_back({*e, nullptr, item.depth + 1});
  }
  return nullptr;
}

// Destroys a tree one node at a time: each node's children are moved out
// onto a work list before it goes, so no destructor recurses far.
template <class Root>
void take_apart(Root root) {
  std::vector<Expr> exprs;
  std::vector<Stmt> stmts;
  if constexpr (std::is_same_v<Root, Expr>)
    exprs.push_back(std::move(root));
  else
    stmts.push_back(std::move(root));
  Children children;
  while (!exprs.empty() || !stmts.empty()) {
    children.clear();
    if (!exprs.empty()) {
      Expr e = std::move(exprs.back());
      exprs.pop_back();
      children_of(e, children);
      for (Expr* c : children.exprs) exprs.push_back(std::move(*c));
    } else {
      Stmt s = std::move(stmts.back());
      stmts.pop_back();
      children_of(s, children);
      for (Expr* c : children.exprs) exprs.push_back(std::move(*c));
      for (Stmt* c : children.stmts) stmts.push_back(std::move(*c));
    }
  }
}

}  // namespace

std::string too_deep_message() {
  return "nested more than " + std::to_string(kMaxNesting) +
         " levels deep (statements and expressions inside one another); split it up";
}

bool limit_nesting(ast::Program& program, Diagnostics& diags) {
  bool ok = true;
  auto body = [&](Stmt& s) {
    if (const SourceSpan* at = too_deep(s)) {
      diags.error(*at, too_deep_message());
      ok = false;
      Stmt empty{ast::Block{}, s.span};
      take_apart(std::exchange(s, std::move(empty)));
    }
  };
  for (auto& t : program.tasks) body(t.body);
  for (auto& s : program.subs) body(s.body);
  for (auto& f : program.functions) body(f.body);
  for (auto& g : program.globals) {
    if (!g.init) continue;
    if (const SourceSpan* at = too_deep(*g.init)) {
      diags.error(*at, too_deep_message());
      ok = false;
      Expr zero{ast::IntLit{0}, g.init->span, std::nullopt};
      take_apart(std::exchange(*g.init, std::move(zero)));
    }
  }
  return ok;
}

}  // namespace rcxc::frontend
