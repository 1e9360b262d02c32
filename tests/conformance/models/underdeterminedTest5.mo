// From OpenModelica testsuite/simulation/modelica/initialization/underdeterminedTest5.mos (loadString content)
// name: underdeterminedTest5
// keywords: initialization, under-determined
// status: correct
//
//  case for initialization of under-determined system
//
within ;
package initializationTests
  model underdeterminedTest5
    Real a(start=-1);
    Real b(start=-2);

  initial equation
    a = 3;

  equation
    when time > 0.5 then
      a = 2;
    end when;

    when initial() then
      b = 1;
    end when;
  end underdeterminedTest5;
end initializationTests;
