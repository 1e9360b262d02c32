// From OpenModelica testsuite/simulation/modelica/initialization/conflictingStartValues.mos (loadString content)
// name:     conflictingStartValues
// keywords: initialization conflict
// status: correct
//
// ticket:4329
type T = Real(start = 10, nominal=100);
model conflictingStartValues
  T x;
  Real y(start = 3);
  Real z(start = -4);
  T a;
  Real b(start = p, nominal=1000);
  Real c(start = -10);
  parameter Real p = 100;
equation
  x = y;
  x + z = 0;
  (x-3)*(x+11) = 0;
  a = b;
  a + c = 0;
  (a-3)*(a+11) = 0;
end conflictingStartValues;
