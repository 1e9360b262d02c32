// From OpenModelica testsuite/simulation/modelica/initialization/discreteTest05.mos (loadString content)
// name: discreteTest5
// keywords: initialization, discrete
// status: correct
//  case for discrete variables during initialization
within ;
package initializationTests
  model discreteTest5_baseModel
    Real x;
    Boolean free;

  initial equation
    x = if free then 1.0 else 2.0;

  equation
    der(x) = if free then 1.0 else 2.0;
    free = false;
  end discreteTest5_baseModel;

  model discreteTest5
    discreteTest5_baseModel bm;
    Real y;

  initial equation
    y = if pre(bm.free) then 1.0 else 2.0;

  equation
    der(y) = if bm.free then 1.0 else 2.0;
  end discreteTest5;
end initializationTests;
