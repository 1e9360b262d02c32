// From OpenModelica testsuite/simulation/modelica/initialization/underdeterminedTest3.mos (loadString content)
// name: underdeterminedTest3
// keywords: initialization, under-determined
// status: correct
//
//  case for initialization of under-determined system
//
within ;
package initializationTests
  model underdeterminedTest3
    Real x(start=1.0);
  equation
    when {time > 0.5} then
      x = 2.0;
    end when;
  end underdeterminedTest3;
end initializationTests;
