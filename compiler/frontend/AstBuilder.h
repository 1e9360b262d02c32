// Builds the AST from an ANTLR parse tree that parsed without errors.
#pragma once

#include "frontend/Ast.h"
#include "support/Diagnostics.h"

namespace antlr4 {
class ParserRuleContext;
}

namespace ldae::frontend {

/// Converts the tree of `storedDefinition` (a parse without syntax errors)
/// of file `fileId` into the AST; reports unsupported constructs that the
/// grammar accepts (redeclarations, inner/outer...).
std::unique_ptr<ast::StoredDefinition>
buildAst(antlr4::ParserRuleContext *storedDefinition, uint32_t fileId,
         const SourceManager &sources, DiagnosticEngine &diags);

} // namespace ldae::frontend
