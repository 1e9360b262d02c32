// Parsing one lsd file into its AST: runs the ANTLR lexer and parser with
// our error listener (diagnostics, never exceptions) and a nesting guard,
// then builds the AST. Nothing of ANTLR leaks out of Parser.cpp/AstBuilder.cpp.
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
