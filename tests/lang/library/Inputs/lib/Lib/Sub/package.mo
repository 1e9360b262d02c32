within Lib;
package Sub
  import Lib.Resistor;
end Sub;
