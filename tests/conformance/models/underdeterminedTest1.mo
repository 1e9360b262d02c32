// From OpenModelica testsuite/simulation/modelica/initialization/underdeterminedTest1.mos (loadString content)
// name: underdeterminedTest1
// keywords: initialization, under-determined
// status: correct
//
//  case for initialization of under-determined system
//
within ;
package initializationTests
  model underdeterminedTest1
    Real x;
    Real y;
  equation
    der(x) = y;
    der(y) = x;
  end underdeterminedTest1;
end initializationTests;
