// The whole lsd language (docs/language.md, /work/shared/LANGUAGE.md): one
// combined lexer + parser grammar. It follows the Modelica 3 concrete syntax
// closely so small single-file Modelica models parse unchanged; constructs
// ldaec does not implement (external functions, stream connectors)
// still parse and are rejected with a diagnostic by the frontend.
// The frontend walks the tree with LsdBaseVisitor (compiler/frontend/AstBuilder.cpp).
grammar Lsd;

// ---------------------------------------------------------------- classes

storedDefinition
    : withinClause? (FINAL? classDefinition ';')* EOF
    ;

withinClause
    : WITHIN name? ';'
    ;

classDefinition
    : ENCAPSULATED? classPrefixes classSpecifier
    ;

classPrefixes
    : PARTIAL? (CLASS | MODEL | OPERATOR? RECORD | BLOCK | EXPANDABLE? CONNECTOR
               | TYPE | PACKAGE | (PURE | IMPURE)? OPERATOR? FUNCTION | OPERATOR)
    ;

classSpecifier
    : IDENT stringComment composition END endName=IDENT            # longClass
    | IDENT '=' basePrefix typeSpecifier arraySubscripts?
      classModification? comment                                   # shortClass
    | IDENT '=' ENUMERATION '(' (enumList | ':')? ')' comment      # enumClass
    | EXTENDS IDENT classModification? stringComment composition
      END endName=IDENT                                            # extendsClass
    ;

basePrefix
    : (INPUT | OUTPUT)?
    ;

enumList
    : enumLiteral (',' enumLiteral)*
    ;

enumLiteral
    : IDENT comment
    ;

composition
    : elementList
      ( PUBLIC elementList
    | PROTECTED elementList
    | equationSection
    | algorithmSection
      )*
      (EXTERNAL languageSpecification? externalCall? annotation? ';')?
      (annotation ';')*
    ;

languageSpecification
    : STRING
    ;

externalCall
    : (componentReference '=')? IDENT '(' expressionList? ')'
    ;

elementList
    : (element ';')*
    ;

element
    : importClause
    | extendsClause
    | REDECLARE? FINAL? INNER? OUTER? REPLACEABLE?
      (classDefinition | componentClause) constrainingClause?
    | annotation
    ;

importClause
    : IMPORT ( IDENT '=' name
             | name ('.' '*' | DOTSTAR)?
             | name '.' '{' importList '}'
             ) comment
    ;

importList
    : IDENT (',' IDENT)*
    ;

extendsClause
    : EXTENDS typeSpecifier classModification? annotation?
    ;

constrainingClause
    : CONSTRAINEDBY name classModification?
    ;

componentClause
    : typePrefix typeSpecifier arraySubscripts? componentList
    ;

typePrefix
    : (FLOW | STREAM)? (DISCRETE | PARAMETER | CONSTANT)? (INPUT | OUTPUT)?
    ;

componentList
    : componentDeclaration (',' componentDeclaration)*
    ;

componentDeclaration
    : IDENT arraySubscripts? modification? (IF expression)? comment
    ;

// -------------------------------------------------------------- modifiers

modification
    : classModification ('=' expression)?
    | '=' expression
    | ':=' expression
    ;

classModification
    : '(' argumentList? ')'
    ;

argumentList
    : argument (',' argument)*
    ;

argument
    : EACH? FINAL? name modification? stringComment         # elementModification
    | REDECLARE EACH? FINAL? REPLACEABLE?
      (classDefinition | componentClause1)                  # elementRedeclaration
    ;

componentClause1
    : typePrefix typeSpecifier IDENT arraySubscripts? modification? comment
    ;

// -------------------------------------------------------------- equations

equationSection
    : INITIAL? EQUATION (equation ';')*
    ;

algorithmSection
    : INITIAL? ALGORITHM (statement ';')*
    ;

equation
    : equationBody comment
    ;

equationBody
    : simpleExpression '=' expression                          # simpleEquation
    | IF expression THEN equationList
        (ELSEIF expression THEN equationList)*
        (ELSE equationList)?
        END IF                                                   # ifEquation
    | FOR forIndices LOOP equationList END FOR                 # forEquation
    | CONNECT '(' componentReference ',' componentReference ')' # connectEquation
    | WHEN expression THEN equationList
        (ELSEWHEN expression THEN equationList)*
        END WHEN                                                 # whenEquation
    | componentReference functionCallArgs                      # callEquation
    ;

equationList
    : (equation ';')*
    ;

statement
    : statementBody comment
    ;

statementBody
    : componentReference (':=' expression | functionCallArgs)    # assignStatement
    | '(' outputExpressionList ')' ':=' componentReference
        functionCallArgs                                         # tupleAssignStatement
    | BREAK                                                    # breakStatement
    | RETURN                                                   # returnStatement
    | IF expression THEN statementList
        (ELSEIF expression THEN statementList)*
        (ELSE statementList)?
        END IF                                                   # ifStatement
    | FOR forIndices LOOP statementList END FOR                # forStatement
    | WHILE expression LOOP statementList END WHILE            # whileStatement
    | WHEN expression THEN statementList
        (ELSEWHEN expression THEN statementList)*
        END WHEN                                                 # whenStatement
    ;

statementList
    : (statement ';')*
    ;

forIndices
    : forIndex (',' forIndex)*
    ;

forIndex
    : IDENT (IN expression)?
    ;

// ------------------------------------------------------------ expressions

expression
    : simpleExpression                                           # plainExpression
    | IF expression THEN expression
      (ELSEIF expression THEN expression)*
      ELSE expression                                            # ifExpression
    ;

simpleExpression
    : logicalExpression (':' logicalExpression (':' logicalExpression)?)?
    ;

logicalExpression
    : logicalTerm (OR logicalTerm)*
    ;

logicalTerm
    : logicalFactor (AND logicalFactor)*
    ;

logicalFactor
    : NOT? relation
    ;

relation
    : arithmeticExpression (relOp arithmeticExpression)?
    ;

relOp
    : '<' | '<=' | '>' | '>=' | '==' | '<>'
    ;

arithmeticExpression
    : addOp? term (addOp term)*
    ;

addOp
    : '+' | '-' | '.+' | '.-'
    ;

// Modelica forbids `a * -b` and `a ^ -b`; we accept them (a sign binds
// tighter than the operator before it) because printed models use them.
term
    : factor (mulOp signedFactor)*
    ;

signedFactor
    : addOp? factor
    ;

mulOp
    : '*' | '/' | DOTSTAR | './'
    ;

factor
    : primary (powOp powOperand)?
    ;

powOperand
    : addOp? primary
    ;

powOp
    : '^' | '.^'
    ;

primary
    : NUMBER                                                     # numberPrimary
    | STRING                                                     # stringPrimary
    | (TRUE | FALSE)                                             # boolPrimary
    | (componentReference | DER | INITIAL | PURE) functionCallArgs # callPrimary
    | componentReference                                         # refPrimary
    | '(' outputExpressionList ')'                               # parenPrimary
    | '[' expressionList (';' expressionList)* ']'               # matrixPrimary
    | '{' arrayArguments '}'                                     # arrayPrimary
    | END                                                        # endPrimary
    ;

typeSpecifier
    : '.'? name
    ;

name
    : IDENT ('.' IDENT)*
    ;

componentReference
    : '.'? refPart ('.' refPart)*
    ;

refPart
    : IDENT arraySubscripts?
    ;

functionCallArgs
    : '(' functionArguments? ')'
    ;

functionArguments
    : functionArgument (',' functionArgument)* (FOR forIndices)?
    ;

functionArgument
    : (IDENT '=')? expression
    | FUNCTION name '(' namedArguments? ')'
    ;

namedArguments
    : IDENT '=' expression (',' IDENT '=' expression)*
    ;

arrayArguments
    : expression (',' expression)* (FOR forIndices)?
    ;

outputExpressionList
    : expression? (',' expression?)*
    ;

expressionList
    : expression (',' expression)*
    ;

arraySubscripts
    : '[' subscript (',' subscript)* ']'
    ;

subscript
    : ':'
    | expression
    ;

comment
    : stringComment annotation?
    ;

stringComment
    : (STRING ('+' STRING)*)?
    ;

annotation
    : ANNOTATION classModification
    ;

// ----------------------------------------------------------------- lexer

ALGORITHM : 'algorithm';
AND : 'and';
ANNOTATION : 'annotation';
BLOCK : 'block';
BREAK : 'break';
CLASS : 'class';
CONNECT : 'connect';
CONNECTOR : 'connector';
CONSTANT : 'constant';
CONSTRAINEDBY : 'constrainedby';
DER : 'der';
DISCRETE : 'discrete';
EACH : 'each';
ELSE : 'else';
ELSEIF : 'elseif';
ELSEWHEN : 'elsewhen';
ENCAPSULATED : 'encapsulated';
END : 'end';
ENUMERATION : 'enumeration';
EQUATION : 'equation';
EXPANDABLE : 'expandable';
EXTENDS : 'extends';
EXTERNAL : 'external';
FALSE : 'false';
FINAL : 'final';
FLOW : 'flow';
FOR : 'for';
FUNCTION : 'function';
IF : 'if';
IMPORT : 'import';
IMPURE : 'impure';
IN : 'in';
INITIAL : 'initial';
INNER : 'inner';
INPUT : 'input';
LOOP : 'loop';
MODEL : 'model';
NOT : 'not';
OPERATOR : 'operator';
OR : 'or';
OUTER : 'outer';
OUTPUT : 'output';
PACKAGE : 'package';
PARAMETER : 'parameter';
PARTIAL : 'partial';
PROTECTED : 'protected';
PUBLIC : 'public';
PURE : 'pure';
RECORD : 'record';
REDECLARE : 'redeclare';
REPLACEABLE : 'replaceable';
RETURN : 'return';
STREAM : 'stream';
THEN : 'then';
TRUE : 'true';
TYPE : 'type';
WHEN : 'when';
WHILE : 'while';
WITHIN : 'within';

DOTSTAR : '.*';

// A Modelica quoted identifier ('r1.v') names one flat variable.
IDENT
    : [a-zA-Z_] [a-zA-Z0-9_]*
    | '\'' (~['\\\r\n] | '\\' .)+ '\''
    ;

NUMBER
    : DIGITS ('.' DIGITS?)? EXPONENT?
    | '.' DIGITS EXPONENT?
    ;

fragment DIGITS : [0-9]+;
fragment EXPONENT : [eE] [+-]? DIGITS;

STRING
    : '"' (~["\\] | '\\' .)* '"'
    ;

WS : [ \t\r\n\f]+ -> skip;
LINE_COMMENT : '//' ~[\r\n]* -> skip;
BLOCK_COMMENT : '/*' .*? '*/' -> skip;
