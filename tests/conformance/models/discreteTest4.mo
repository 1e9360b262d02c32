// From OpenModelica testsuite/simulation/modelica/initialization/discreteTest04.mos (loadString content)
// name: discreteTest4
// keywords: initialization, discrete
// status: correct
//  case for discrete variables during initialization
within ;
package initializationTests
  model discreteTest4
    Integer i1(start=1, fixed=false); // i1 = 3 | pre(i1) = 1
    Integer i2(start=1, fixed=false); // i2 = 2 | pre(i2) = 1
    Integer i3(start=1, fixed=true);  // i3 = 3 | pre(i3) = 1

    Real x1;  // 1.0
    Real x2;  // 1.0
    Real x3;  // 1.0
    
  initial equation
    pre(i1) = 1;
    pre(i2) = 1;
    
    x1 = pre(i1);
    x2 = pre(i2);
    x3 = pre(i3);

  equation 
    der(x1) = 0;
    der(x2) = 0;
    der(x3) = 0;
    
    i1 = if time > 0.5 then 2 else 3;
    i2 = if time < 0.5 then 2 else 3;
    i3 = if time > 0.5 then 2 else 3;
  end discreteTest4;
end initializationTests;
