// From OpenModelica testsuite/simulation/modelica/initialization/underdeterminedTest2.mos (loadString content)
// name: underdeterminedTest2
// keywords: initialization, under-determined
// status: correct
//
//  case for initialization of under-determined system
//
within ;
package initializationTests
  model underdeterminedTest2
    Real x;
    Real y;
  initial equation
    x = 1;
  equation
    der(x) = y;
    der(y) = x;
  end underdeterminedTest2;
end initializationTests;
