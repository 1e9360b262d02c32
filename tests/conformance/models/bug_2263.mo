// From OpenModelica testsuite/simulation/modelica/initialization/bug_2263.mos (loadString content)
// name: bug_2263
// keywords: initialization
// status: correct
within ;
package initializationTests
  model bug_2263
    Real x(start=0, fixed=true);
    Real d(start=0, fixed=true);
  initial equation
    pre(x) = -1;
  equation
    der(x) = 0;
    when sample(0.0, 1.0) then
      d = pre(x);
    end when;
  end bug_2263;
end initializationTests;

// var    | equation
// -------+--------------------------------------
// x      | x = 0       (implicit)
// der(x) | der(x) = 0  (equation)
// pre(x) | pre(x) = -1 (initial equation)
//        | x = pre(x)  (implicit)
// d      | d = pre(d)  (equation: inactive when)
// pre(d) | pre(d) = 0  (implicit)
// -------+--------------------------------------
// 5      | 6
