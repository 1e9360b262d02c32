// Which variables and equations of a flat model are discrete (LANGUAGE.md
// "Discrete behaviour"): the one classification the balance check and the
// events pass share, so both count the continuous system alike.
#pragma once

#include "ir/Model.h"

#include <vector>

namespace ldae::ir {

/// By VarId: Boolean, Integer and discrete Real variables, the built-in
/// calls kept as variables (initial(), sample()) and every variable a
/// when-clause assigns.
std::vector<bool> discreteVariables(const Model &m);

/// True for a relation that generates events: a Compare outside noEvent
/// whose operands read a continuous variable or time.
bool isEventRelation(ExprRef e, const std::vector<bool> &discrete);

/// floor() and ceil() (integer() is floor): piecewise constant, changing
/// at events the events pass makes of their crossings.
bool isStepFunction(ExprRef e);

/// True when `e` reads a continuous variable outside the event relations
/// and step functions (whose values are discrete): an equation that does
/// not is an equation of discrete values (`on = time > 0.5`, `off = s <
/// 0`, `n = integer(x)`).
bool readsContinuous(ExprRef e, const std::vector<bool> &discrete);

/// True for an equation of discrete values: it reads a discrete variable
/// and no continuous one outside event relations.
bool isDiscreteEquation(ExprRef residual, const std::vector<bool> &discrete);

} // namespace ldae::ir
