// From OpenModelica testsuite/simulation/modelica/initialization/discreteTest01.mos (loadString content)
// name: discreteTest1
// keywords: initialization, discrete
// status: correct
//  case for discrete variables during initialization
within ;
package initializationTests
  model discreteTest1
    discrete Real d1(start=1, fixed=false); // d1 = 1.1 | pre(d1) = 1.0
    discrete Real d2(start=1, fixed=false); // d2 = 1.0 | pre(d2) = 0.9
    discrete Real d3(start=1, fixed=true);  // d3 = 1.1 | pre(d3) = 1.0

    Real x1;  // 1.0
    Real x2;  // 0.9
    Real x3;  // 1.0
    
  initial equation 
    pre(d1) = 1;
    d2 = 1;

    x1 = pre(d1);
    x2 = pre(d2);
    x3 = pre(d3);

  equation 
    der(x1) = 0;
    der(x2) = 0;
    der(x3) = 0;
   
    when {initial(), sample(0.1, 0.1)} then
      d1 = pre(d1) + 0.1;
      d2 = pre(d2) + 0.1;
      d3 = pre(d3) + 0.1;
    end when;
  end discreteTest1;
end initializationTests;
