// Parsing one lsd file into its AST: runs our lexer (Lexer.h) and the ANTLR
// parser with our error strategy (diagnostics, never exceptions) and a
// nesting guard, then builds the AST. Nothing of ANTLR leaks out of the
// frontend's Lexer, Parser and AstBuilder files.
#pragma once

#include "frontend/Ast.h"
#include "support/Diagnostics.h"

#include <memory>

namespace ldae::frontend {

/// Deepest grammar-rule nesting accepted (parenthesized expressions,
/// nested if/for...); deeper input is rejected with a diagnostic instead of
/// overflowing the stack.
inline constexpr unsigned kMaxParseDepth = 1200;

/// Parses the file registered as `fileId`; nullptr after reporting errors.
std::unique_ptr<ast::StoredDefinition>
parseFile(uint32_t fileId, const SourceManager &sources, DiagnosticEngine &diags);

} // namespace ldae::frontend
