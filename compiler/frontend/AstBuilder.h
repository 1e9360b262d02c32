// Builds the AST from an ANTLR parse tree that parsed without errors.
#pragma once

#include "frontend/Ast.h"
#include "support/Diagnostics.h"

#include <string>

namespace antlr4 {
class ParserRuleContext;
}

namespace ldae::frontend {

/// Converts the tree of `storedDefinition` (a parse without syntax errors)
/// of file `fileId`, whose characters as the lexer read them are `chars`
/// (token indices point into them), into the AST; reports unsupported constructs that the
/// grammar accepts (redeclarations, inner/outer...).
std::unique_ptr<ast::StoredDefinition>
buildAst(antlr4::ParserRuleContext *storedDefinition, uint32_t fileId,
         const std::u32string &chars, DiagnosticEngine &diags);

} // namespace ldae::frontend
