// From OpenModelica testsuite/simulation/modelica/initialization/discreteTest10.mos (loadString content)
// name: discreteTest10
// keywords: initialization, discrete
// status: correct
//  case for when-clauses in algorithm sections
within ;
package initializationTests
  model discreteTest10
    Real x(start=1);
    Real y;
  initial equation
    y = 4;
  equation
    when time > 0.5 then
      x = 0.5;
    end when;
    y = x^2;
  end discreteTest10;
end initializationTests;
