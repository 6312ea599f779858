# The datasheet's table, row by row: input registers (3xxxx, function 04), the reference numbers kept as
# printed, float32 with the low word first (CDAB), already in engineering units (scale 1).
from modbus_edu.exercises import check

answer = """name,table,address,type,order,scale,unit
voltage,input,30001,float32,CDAB,1,V
current,input,30007,float32,CDAB,1,A
active_power,input,30013,float32,CDAB,1,W
frequency,input,30071,float32,CDAB,1,Hz
import_energy,input,30073,float32,CDAB,1,kWh
"""
check("16.1", answer)
