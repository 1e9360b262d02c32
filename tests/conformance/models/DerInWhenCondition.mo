// From OpenModelica testsuite/simulation/modelica/events/derInWhenCondition.mos (loadString content)
// name: derInWhenCondition
// keywords: when, der, zero crossing, index reduction
// status: correct
//  der() of an algebraic variable in the condition of a when-equation whose body
//  only has side effects. Such a when-equation is a removed equation, but its
//  condition is still evaluated, so the variable has to become a state and get a
//  differentiated equation just as in any other equation.
model DerInWhenCondition
  Real x(start = 0, fixed = true);
  Real y;
equation
  der(x) = 1;
  y = 2 * sin(x);
  when der(y) < 0 then
    assert(y < 100.0, "y stays bounded");
  end when;
end DerInWhenCondition;
