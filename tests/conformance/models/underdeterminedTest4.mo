// From OpenModelica testsuite/simulation/modelica/initialization/underdeterminedTest4.mos (loadString content)
// name: underdeterminedTest4
// keywords: initialization, under-determined
// status: correct
//
//  case for initialization of under-determined system
//
within ;
package initializationTests
  model underdeterminedTest4
    parameter Real p(start=1, fixed=false);
  end underdeterminedTest4;
end initializationTests;
