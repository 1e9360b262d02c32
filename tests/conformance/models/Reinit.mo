// From OpenModelica testsuite/simulation/modelica/events/Reinit.mos (loadString content)
// name: Reinit
// keywords: event, reinit
// status: correct
//   This test is used to check multiple when conditions for a reinit statement
package TestReinit
  model test1
    Real x;
  initial equation
    x = 0;
  equation
    der(x) = 0;

    when {time > 0.1, time > 0.2} then
      reinit(x, x+1);
    end when;
  end test1;
  model test2
    Real x, y, z;
  initial equation
    x = 0;
    y = -1;
    z = 0;
  equation
    der(x) = sin(time*10);
    der(y) = cos(time*10);
    der(z) = sin(time*10);
    when {time > 0.1, time > 0.2} then
      reinit(x, x+1);
      reinit(y, y+1);
    elsewhen time>0.5 then 
      reinit(x, x-1);
      reinit(y, y-1);
    elsewhen time>0.7 then
      reinit(z, 0);
    end when;
  end test2;

end TestReinit;
